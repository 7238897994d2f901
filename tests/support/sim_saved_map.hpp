#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/localization/localization_map.hpp"
#include "core/points/voxel_downsample.hpp"
#include "drivers/sim/simulator.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

namespace strata::test {

/// The localization map a run of `scans` stop-and-go scans through `world` would save (seed `seed`), every
/// scan a keyframe at its true pose, thinned as the pose graph thins them.
inline LocalizationMap saved_map_of_run(const std::shared_ptr<const sim::World>& world, std::size_t scans,
                                        std::uint64_t seed = 1) {
  std::vector<KeyframePose> keyframes;
  sim::Simulator run(world, {.seed = seed});
  while (keyframes.size() < scans) {
    run.step(0.01);
    for (const ScanEvent& scan : run.take_scans()) {
      auto keyframe = std::make_shared<Keyframe>();
      keyframe->points = voxel_downsample(pipeline::points_in_base(scan), 0.2);
      keyframes.push_back({keyframe, scan.truth->to_isometry()});
    }
  }
  return make_localization_map(keyframes);
}

}  // namespace strata::test

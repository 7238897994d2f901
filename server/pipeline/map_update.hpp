#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>

#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"

namespace strata::pipeline {

/// What the mapping worker tells its listeners (the navigator) after every map change, on the mapping
/// thread: the map, the drivable map at the robot's level just recomputed, and the map-frame point the
/// robot stands on. A listener copies what it needs and returns quickly: the mapping waits for it.
struct MapUpdate {
  const MlsMap& map;
  const DrivableMap& drivable;
  Eigen::Vector3d robot_ground;
  std::uint64_t version = 0;
  /// The drivable map at the robot's level over the whole map (what the PGM/YAML export holds), made when
  /// asked for, on the mapping thread or after it stopped; null without a robot position.
  std::function<std::shared_ptr<const DrivableMap>()> whole_level;
};

using MapUpdateListener = std::function<void(const MapUpdate&)>;

}  // namespace strata::pipeline

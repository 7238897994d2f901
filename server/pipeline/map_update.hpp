#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>

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
};

using MapUpdateListener = std::function<void(const MapUpdate&)>;

}  // namespace strata::pipeline

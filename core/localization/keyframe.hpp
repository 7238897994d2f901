#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "core/points/point_cloud.hpp"

namespace strata {

/// A registered scan kept for the pose graph (docs/architecture.md 4.1): its points in the base frame,
/// thinned to one per voxel of KeyframeOptions::voxel (what loop closures register and the map is rebuilt
/// from), and where the scan-to-map localizer put it. Immutable once made: shared between the scan path
/// and the background optimizer without copies.
struct Keyframe {
  double stamp = 0.0;
  PointCloud points;
  /// Metres driven from the first keyframe to this one: loops are only looked for between keyframes
  /// far apart along the way.
  double travelled = 0.0;
};
using KeyframePtr = std::shared_ptr<const Keyframe>;

}  // namespace strata

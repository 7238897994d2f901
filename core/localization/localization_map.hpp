#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/localization/keyframe.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// What a saved map keeps for localizing in it (docs/architecture.md 4.1, "Localizing in a saved map"):
/// the points the pose graph's keyframes hold for loop closures, placed at the keyframes' optimized poses
/// and thinned to one per voxel over them all, and where the keyframes were. The MLS map alone is not
/// enough: a cell keeps heights, not where on a wall a point lay, and a wall cell's centre is up to half
/// a cell off the wall.
struct LocalizationMap {
  double voxel = 0.1;  ///< metres: one point per voxel of this size
  /// Map frame. Floats: the map's own heights are floats, and a kilometre from the origin a float still
  /// resolves a tenth of a millimetre.
  std::vector<Eigen::Vector3f> points;
  /// Where the robot that made the map was at each keyframe (map frame, oldest first): the places a robot
  /// driving the same map is likely to be found again.
  std::vector<Eigen::Isometry3d> keyframe_poses;

  [[nodiscard]] bool empty() const { return points.empty(); }
  /// The points as the registration takes them.
  [[nodiscard]] PointCloud cloud() const;
};

/// `keyframes`' points at their poses, one per `voxel` (the first keyframe to reach a voxel keeps it).
[[nodiscard]] LocalizationMap make_localization_map(const std::vector<KeyframePose>& keyframes,
                                                    double voxel = 0.1);

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A registered scan kept for the pose graph (docs/architecture.md 4.1). Immutable once made: shared
/// between the scan path, the background optimizer and the map rebuild without copies.
struct Keyframe {
  double stamp = 0.0;
  /// Base frame, one point per GraphLocalizerOptions::keyframe_voxel: what loop closures register.
  PointCloud points;
  /// Base frame, one point per GraphLocalizerOptions::keyframe_map_voxel (the map's cell size): what the
  /// map is rebuilt from when the keyframe's pose moves. Floats: the map stores heights as floats anyway,
  /// and it halves the memory per km.
  std::vector<Eigen::Vector3f> map_points;
  Eigen::Vector3d sensor_origin = Eigen::Vector3d::Zero();  ///< base frame: where the rays start
  /// Where the scan path put it when it was made (map frame): the pose its scan went into the live map
  /// with, so the map rebuild knows what moved.
  Eigen::Isometry3d mapped_pose = Eigen::Isometry3d::Identity();
  /// Which way was up, from the base's IMU (none without one): the keyframe's attitude prior.
  std::optional<GravityReading> gravity;
  /// Metres driven from the first keyframe to this one: loops are only looked for between keyframes
  /// far apart along the way.
  double travelled = 0.0;
};
using KeyframePtr = std::shared_ptr<const Keyframe>;

/// A keyframe and its current pose estimate in the map frame.
struct KeyframePose {
  KeyframePtr keyframe;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

}  // namespace strata

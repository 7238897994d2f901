#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/localization/heading_drift.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// One registered scan as a keyframe keeps it for rebuilding the map, in the keyframe's base frame. Floats:
/// the map stores heights as floats anyway, and it halves the memory per km.
struct KeyframeScan {
  Eigen::Vector3f sensor_origin = Eigen::Vector3f::Zero();  ///< where its rays start
  Eigen::Vector3f ground = Eigen::Vector3f::Zero();         ///< its base origin: the ground it drove on
  /// One point per GraphLocalizerOptions::keyframe_map_voxel (the map's cell size), over the keyframe's
  /// scans: the voxels no earlier scan of the keyframe reached.
  std::vector<Eigen::Vector3f> points;
};

/// A registered scan kept for the pose graph (docs/architecture.md 4.1). Immutable once made: shared
/// between the scan path, the background optimizer and the map rebuild without copies.
struct Keyframe {
  double stamp = 0.0;
  /// Base frame, one point per GraphLocalizerOptions::keyframe_voxel: what loop closures register.
  PointCloud points;
  /// What the map is rebuilt from when the keyframe's pose moves: the scans registered since the previous
  /// keyframe and then its own, oldest first. A 10 Hz lidar makes a keyframe every ten or so scans: built
  /// from the keyframes' own scans alone, the map lost the ground rings between them and the track the
  /// robot drove (it sees no ground within 5 m), and goals near the robot had no way to them.
  std::vector<KeyframeScan> scans;
  /// Where the scan path put it when it was made (map frame): the pose its scan went into the live map
  /// with, so the map rebuild knows what moved.
  Eigen::Isometry3d mapped_pose = Eigen::Isometry3d::Identity();
  /// Which way was up, from the base's IMU (none without one): the keyframe's attitude prior.
  std::optional<GravityReading> gravity;
  /// Metres driven from the first keyframe to this one: loops are only looked for between keyframes
  /// far apart along the way.
  double travelled = 0.0;
  /// The odometry's heading here and the seconds of motion before (none for a base without odometry):
  /// what the odometry's heading drift is fitted to (fit_heading_drift; its estimated_heading unset).
  std::optional<HeadingSample> odometry_heading;
};
using KeyframePtr = std::shared_ptr<const Keyframe>;

/// A keyframe and its current pose estimate in the map frame.
struct KeyframePose {
  KeyframePtr keyframe;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// The keyframe a registered scan came after, and that keyframe's pose in the frame the scan was
/// registered in: a map rebuild that moves the keyframe moves the scan with it. The scans after the newest
/// keyframe are no keyframe's yet; mapped again at their own poses, they stayed in the frame from before
/// the loop closure, a ramp's deck 0.17 m above where the rebuilt map had it, and closed the robot's way.
struct KeyframeAnchor {
  KeyframePtr keyframe;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

}  // namespace strata

#pragma once

#include <Eigen/Geometry>

#include "core/geometry/pose.hpp"

namespace strata {

/// The robot's global pose as odometry corrected by scan matching (thesis section 4.2). Each accepted
/// registration yields the correction (R, t) that moved the odometry-placed scan onto the map; the
/// corrections accumulate as Rg <- R Rg, tg <- R tg + t (eqs. 4.13-4.14, composed on the left to match
/// eq. 4.14), and the pose is the accumulated correction applied to the odometry pose (eqs. 4.15-4.16).
class GlobalPose {
 public:
  /// Adds one registration's correction, expressed in the map frame.
  void apply_correction(const Eigen::Isometry3d& correction);

  /// The full 6-DoF pose for an odometry pose: p = Rg p_odom + tg (eq. 4.16) for the position, and
  /// roll/pitch/yaw of Rg times the odometry heading (eqs. 4.17-4.21, via Pose3::from_isometry).
  [[nodiscard]] Pose3 pose(const Pose2& odometry) const;
  [[nodiscard]] Eigen::Isometry3d pose_isometry(const Pose2& odometry) const;

  [[nodiscard]] const Eigen::Isometry3d& correction() const { return correction_; }

 private:
  Eigen::Isometry3d correction_ = Eigen::Isometry3d::Identity();
};

}  // namespace strata

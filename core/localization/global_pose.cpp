#include "core/localization/global_pose.hpp"

namespace strata {

void GlobalPose::apply_correction(const Eigen::Isometry3d& correction) {
  // Rg <- R Rg (eq. 4.13), tg <- R tg + t (eq. 4.14): the later correction acts on the earlier result.
  Eigen::Isometry3d next = Eigen::Isometry3d::Identity();
  next.linear() = correction.linear() * correction_.linear();
  next.translation() = correction.linear() * correction_.translation() + correction.translation();
  // Keep Rg a rotation: rounding in the product drifts it off SO(3), and because each new correction is
  // computed through the inverse of the last pose (a transpose, exact only for rotations), the drift
  // compounds geometrically; within 50 scans the map frame shrank to nothing before this renormalisation.
  next.linear() = Eigen::Quaterniond(next.linear()).normalized().toRotationMatrix();
  correction_ = next;
}

Eigen::Isometry3d GlobalPose::pose_isometry(const Pose2& odometry) const {
  // p = (x_odom, y_odom, 0) (eq. 4.15), p <- Rg p + tg (eq. 4.16); the heading turns with Rg likewise.
  return correction_ * Pose3::from_pose2(odometry).to_isometry();
}

Pose3 GlobalPose::pose(const Pose2& odometry) const {
  return Pose3::from_isometry(pose_isometry(odometry));
}

}  // namespace strata

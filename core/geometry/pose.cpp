#include "core/geometry/pose.hpp"

#include <cmath>

#include "core/geometry/angles.hpp"

namespace strata {

Pose2 Pose2::compose(const Pose2& delta) const {
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  return {x + c * delta.x - s * delta.y, y + s * delta.x + c * delta.y, wrap_angle(theta + delta.theta)};
}

Pose2 Pose2::relative_to(const Pose2& from) const {
  const double c = std::cos(from.theta);
  const double s = std::sin(from.theta);
  const double dx = x - from.x;
  const double dy = y - from.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(theta - from.theta)};
}

Eigen::Isometry3d Pose3::to_isometry() const {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  transform.translation() = position;
  return transform;
}

Pose3 Pose3::from_isometry(const Eigen::Isometry3d& transform) {
  const Eigen::Matrix3d& r = transform.linear();
  Pose3 pose;
  pose.position = transform.translation();
  // Thesis eqs. 4.18-4.21, taking the pitch in [-pi/2, pi/2] so cos(pitch) >= 0: dividing both atan2
  // arguments by it (as the thesis writes) then changes nothing, and is left out for accuracy.
  const double cos_pitch = std::hypot(r(0, 0), r(1, 0));
  if (cos_pitch > 1e-9) {
    pose.pitch = std::atan2(-r(2, 0), cos_pitch);
    pose.roll = std::atan2(r(2, 1), r(2, 2));
    pose.yaw = std::atan2(r(1, 0), r(0, 0));
  } else {
    // Gimbal lock (pitch = +-90 degrees): roll and yaw turn about the same axis; put it all in yaw.
    pose.pitch = std::copysign(kPi / 2, -r(2, 0));
    pose.roll = 0.0;
    pose.yaw = std::atan2(-r(0, 1), r(1, 1));
  }
  return pose;
}

Pose3 Pose3::from_pose2(const Pose2& pose, double z) {
  Pose3 result;
  result.position = {pose.x, pose.y, z};
  result.yaw = pose.theta;
  return result;
}

double heading_of(const Eigen::Isometry3d& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  return angle > 0.0 ? Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix()
                     : Eigen::Matrix3d::Identity();
}

}  // namespace strata

#pragma once

#include <Eigen/Geometry>

namespace strata {

/// A pose on the ground plane: what wheel odometry measures.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;  ///< heading, radians, counter-clockwise from +x

  /// This pose followed by `delta` expressed in this pose's frame.
  [[nodiscard]] Pose2 compose(const Pose2& delta) const;
  /// The motion that takes `from` to this pose, expressed in `from`'s frame.
  [[nodiscard]] Pose2 relative_to(const Pose2& from) const;
};

/// A full 6-DoF pose. Angles are the thesis's roll (about x), pitch (about y) and yaw (about z), applied
/// as R = Rz(yaw) * Ry(pitch) * Rx(roll): the convention of thesis eqs. 4.17-4.21 and of ROS.
struct Pose3 {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;

  [[nodiscard]] Eigen::Isometry3d to_isometry() const;
  /// Extracts roll, pitch and yaw from a rotation, taking the pitch in [-pi/2, pi/2] (the "closest"
  /// of the two solutions of thesis eq. 4.18-4.19).
  [[nodiscard]] static Pose3 from_isometry(const Eigen::Isometry3d& transform);
  [[nodiscard]] static Pose3 from_pose2(const Pose2& pose, double z = 0.0);
};

/// The heading of a pose: where its x axis points in the ground plane, radians counter-clockwise from +x
/// (its yaw, when roll and pitch are small).
[[nodiscard]] double heading_of(const Eigen::Isometry3d& pose);

/// The rotation a rotation vector (axis times angle, radians) stands for; the identity for the zero vector.
[[nodiscard]] Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& rotation_vector);

}  // namespace strata

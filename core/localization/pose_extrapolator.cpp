#include "core/localization/pose_extrapolator.hpp"

#include <algorithm>
#include <cmath>

#include "core/localization/gravity_leveling.hpp"

namespace strata {
namespace {

// About 200 s of samples at 100 Hz: beyond that without a scan, the height is the carried one.
constexpr std::size_t kMaxSteps = 20000;

/// Roll and pitch (R = Rz(yaw) Ry(pitch) Rx(roll)) of a base whose accelerometer reads `up`: up is
/// R^T z = (-sin pitch, sin roll cos pitch, cos roll cos pitch).
Eigen::Vector2d roll_pitch(const GravityReading& gravity) {
  const Eigen::Vector3d& up = gravity.up_in_base;
  return {std::atan2(up.y(), up.z()), std::atan2(-up.x(), std::hypot(up.y(), up.z()))};
}

}  // namespace

void PoseExtrapolator::add_sample(double stamp, const Pose3& odometry,
                                  const std::optional<GravityReading>& gravity) {
  if (!steps_.empty() && stamp < steps_.back().stamp)
    steps_.clear();
  gravity_ = gravity && GravityLeveling::usable(*gravity)
                 ? std::optional(GravityLeveling::without_mounting(*gravity, mounting_))
                 : std::nullopt;
  Step step{stamp, odometry, steps_.empty() ? 0.0 : steps_.back().climb};
  if (!steps_.empty() && gravity_) {
    // The way driven, in the heading's frame: wheels count it along the ground the reading says the base
    // stands on, the base's own x-y plane, whose rise is R's last row: dz = -sin(pitch) dx +
    // cos(pitch) sin(roll) dy.
    const Pose3& before = steps_.back().odometry;
    const Eigen::Vector2d way =
        Eigen::Rotation2Dd(-before.yaw) * (odometry.position - before.position).head<2>();
    const Eigen::Vector2d tilt = roll_pitch(*gravity_);
    step.climb += -std::sin(tilt.y()) * way.x() + std::cos(tilt.y()) * std::sin(tilt.x()) * way.y();
  }
  steps_.push_back(step);
  if (steps_.size() > kMaxSteps)
    steps_.pop_front();
}

void PoseExtrapolator::set_correction(const Eigen::Isometry3d& map_from_odom,
                                      std::optional<double> scan_stamp) {
  map_from_odom_ = map_from_odom;
  scan_stamp_ = scan_stamp;
  // Keep the last step taken at or before the scan: the height there is the correction's.
  if (scan_stamp)
    while (steps_.size() > 1 && steps_[1].stamp <= *scan_stamp)
      steps_.pop_front();
}

Pose3 PoseExtrapolator::estimate() const {
  if (steps_.empty())
    return Pose3::from_isometry(map_from_odom_);
  const Step& now = steps_.back();
  Eigen::Isometry3d carried = map_from_odom_ * now.odometry.to_isometry();
  if (velocity_ && scan_stamp_ && now.stamp > *scan_stamp_) {
    const double dt = std::min(now.stamp - *scan_stamp_, kMaxCarried);
    carried =
        carried *
        Pose3::from_pose2(Pose2{velocity_->x * dt, velocity_->y * dt, velocity_->theta * dt}).to_isometry();
  }
  Pose3 pose = Pose3::from_isometry(carried);
  const Step& at_scan = steps_.front();
  if (!gravity_ || !scan_stamp_ || at_scan.stamp > *scan_stamp_)
    return pose;  // no reading now, or the samples do not reach back to the scan: carried as it is
  pose.position.z() =
      (map_from_odom_ * at_scan.odometry.to_isometry()).translation().z() + now.climb - at_scan.climb;
  const Eigen::Vector2d tilt = roll_pitch(*gravity_);
  pose.roll = tilt.x();
  pose.pitch = tilt.y();
  return pose;
}

}  // namespace strata

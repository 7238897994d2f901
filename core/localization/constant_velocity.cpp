#include "core/localization/constant_velocity.hpp"

#include <algorithm>
#include <cmath>

namespace strata {

Pose2 ConstantVelocityPrediction::predict(double stamp) const {
  if (!last_)
    return {};
  if (!velocity_)
    return last_->odometry;
  const double dt = std::max(0.0, stamp - last_->stamp);
  return last_->odometry.compose({velocity_->x * dt, velocity_->y * dt, velocity_->theta * dt});
}

std::optional<Eigen::Isometry3d> ConstantVelocityPrediction::predict_pose(double stamp) const {
  if (!last_ || !velocity_)
    return std::nullopt;
  const double dt = std::max(0.0, stamp - last_->stamp);
  return last_->pose *
         Pose3::from_pose2({velocity_->x * dt, velocity_->y * dt, velocity_->theta * dt}).to_isometry();
}

GuessUncertainty ConstantVelocityPrediction::uncertainty(double stamp) const {
  const double dt = last_ ? std::max(0.0, stamp - last_->stamp) : 0.0;
  const GuessUncertainty anything{options_.max_speed * dt, options_.max_turn_rate * dt, false};
  if (!velocity_)
    return anything;
  // A change of motion over dt, but never more than the fastest base could have moved at all.
  const double half_dt2 = 0.5 * dt * dt;
  return {std::min(anything.translation, options_.max_acceleration * half_dt2),
          std::min(anything.rotation, options_.max_angular_acceleration * half_dt2)};
}

void ConstantVelocityPrediction::update(double stamp, const Pose2& odometry, const Eigen::Isometry3d& pose,
                                        bool registered, bool map_moved) {
  if (last_ && registered && !map_moved && stamp > last_->stamp) {
    const Eigen::Isometry3d moved = last_->pose.inverse() * pose;
    const double dt = stamp - last_->stamp;
    const double turn = heading_of(moved);
    velocity_ = Pose2{moved.translation().x() / dt, moved.translation().y() / dt, turn / dt};
  }
  last_ = Scan{stamp, odometry, pose};
}

}  // namespace strata

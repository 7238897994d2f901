#include "drivers/sim/diff_drive_base.hpp"

#include <algorithm>
#include <cmath>

namespace strata::sim {
namespace {

double approach(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace

DiffDriveBase::DiffDriveBase(DiffDriveLimits limits, Pose2 start) : limits_(limits), pose_(start) {}

DiffDriveBase::Step DiffDriveBase::preview(const VelocityCommand& command, double dt) const {
  const double v_target = std::clamp(command.v, -limits_.max_speed, limits_.max_speed);
  const double w_target = std::clamp(command.w, -limits_.max_turn_rate, limits_.max_turn_rate);
  Step step;
  step.velocity.v = approach(velocity_.v, v_target, limits_.max_accel * dt);
  step.velocity.w = approach(velocity_.w, w_target, limits_.max_turn_accel * dt);

  // Exact integration along the arc driven at constant (v, w) over dt.
  const double distance = step.velocity.v * dt;
  const double turn = step.velocity.w * dt;
  Pose2 delta{distance, 0.0, turn};
  if (std::abs(turn) > 1e-9) {
    const double radius = distance / turn;
    delta.x = radius * std::sin(turn);
    delta.y = radius * (1.0 - std::cos(turn));
  }
  step.pose = pose_.compose(delta);
  const double half_track = 0.5 * limits_.wheel_separation;
  step.wheels = {distance - turn * half_track, distance + turn * half_track};
  return step;
}

void DiffDriveBase::apply(const Step& step) {
  pose_ = step.pose;
  velocity_ = step.velocity;
}

void DiffDriveBase::halt() {
  velocity_ = {};
}

}  // namespace strata::sim

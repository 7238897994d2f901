#include "drivers/sim/loop_driver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace strata::sim {

LoopDriver::LoopDriver(std::vector<Waypoint> loop, double cruise_speed, double lookahead)
    : loop_(std::move(loop)), cruise_speed_(cruise_speed), lookahead_(lookahead) {
  if (loop_.size() < 2)
    throw std::invalid_argument("LoopDriver needs at least two waypoints");
}

LoopDriver LoopDriver::yard_loop() {
  return LoopDriver(
      {{4.0, -3.0}, {6.5, 0.0}, {4.0, 3.0}, {0.0, 4.0}, {-4.0, 3.0}, {-4.5, -1.0}, {-2.0, -4.0}}, 0.6, 1.0);
}

VelocityCommand LoopDriver::command(const Pose2& pose) {
  // Advance to the next waypoint once the current one is within the lookahead distance.
  for (std::size_t guard = 0; guard < loop_.size(); ++guard) {
    const Waypoint& target = loop_[target_];
    if (std::hypot(target.x - pose.x, target.y - pose.y) > lookahead_)
      break;
    target_ = (target_ + 1) % loop_.size();
  }
  const Waypoint& target = loop_[target_];
  const Pose2 local = Pose2{target.x, target.y, 0.0}.relative_to(pose);
  const double distance_sq = local.x * local.x + local.y * local.y;
  // Pure pursuit: the arc through the target has curvature 2 y / d^2 in the robot frame.
  const double curvature = 2.0 * local.y / std::max(distance_sq, 1e-6);
  // Slow down for sharp turns, and turn on the spot when the target is behind.
  const double speed = local.x > 0.0 ? cruise_speed_ / (1.0 + 1.5 * std::abs(curvature)) : 0.0;
  const double turn = local.x > 0.0 ? speed * curvature : std::copysign(1.0, local.y);
  return {speed, turn};
}

}  // namespace strata::sim

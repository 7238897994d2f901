#include "drivers/sim/route_driver.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace strata::sim {

RouteDriver::RouteDriver(std::vector<Eigen::Vector2d> route, double cruise_speed, double arrive_radius)
    : route_(std::move(route)), cruise_speed_(cruise_speed), arrive_radius_(arrive_radius) {}

VelocityCommand RouteDriver::command(const Pose2& pose) {
  if (route_.size() < 2)
    return {};
  // Straight lines between waypoints, turning on the spot at each: a wheelchair's way through doors
  // and along corridors, where cutting corners would scrape the walls.
  Pose2 local = Pose2{route_[target_].x(), route_[target_].y(), 0.0}.relative_to(pose);
  for (std::size_t guard = 0; guard < route_.size() && std::hypot(local.x, local.y) < arrive_radius_;
       ++guard) {
    target_ = (target_ + 1) % route_.size();
    local = Pose2{route_[target_].x(), route_[target_].y(), 0.0}.relative_to(pose);
  }
  const double heading_error = std::atan2(local.y, local.x);
  const double turn = std::clamp(2.0 * heading_error, -1.0, 1.0);
  if (std::abs(heading_error) > 0.35)
    return {0.0, turn};  // about 20 degrees off: turn first
  // Slow down towards the waypoint (it may be a corner), never below a crawl.
  const double distance = std::hypot(local.x, local.y);
  const double speed = std::clamp(0.8 * distance, 0.15, cruise_speed_) * std::cos(heading_error);
  return {speed, turn};
}

}  // namespace strata::sim

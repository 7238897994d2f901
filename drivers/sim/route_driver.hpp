#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/geometry/pose.hpp"
#include "drivers/sim/diff_drive_base.hpp"

namespace strata::sim {

/// Drives a closed route of waypoints forever: the simulator's demo behaviour until goals come from the
/// planner. Steers on the true pose, as a line-following robot would. An empty route keeps it standing.
class RouteDriver {
 public:
  RouteDriver(std::vector<Eigen::Vector2d> route, double cruise_speed = 0.6, double arrive_radius = 0.25);

  [[nodiscard]] VelocityCommand command(const Pose2& pose);
  [[nodiscard]] std::size_t target_index() const { return target_; }

 private:
  std::vector<Eigen::Vector2d> route_;
  double cruise_speed_;
  double arrive_radius_;
  std::size_t target_ = 0;
};

}  // namespace strata::sim

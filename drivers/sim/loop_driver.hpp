#pragma once

#include <cstddef>
#include <vector>

#include "core/geometry/pose.hpp"
#include "drivers/sim/diff_drive_base.hpp"

namespace strata::sim {

struct Waypoint {
  double x = 0.0;
  double y = 0.0;
};

/// Drives a closed loop of waypoints forever with pure pursuit: the demo behaviour of the simulator
/// until goals come from the planner. Steers on the ground-truth pose, as a line follower would.
class LoopDriver {
 public:
  LoopDriver(std::vector<Waypoint> loop, double cruise_speed, double lookahead);

  /// A loop around the yard world's crate that keeps clear of the other boxes.
  [[nodiscard]] static LoopDriver yard_loop();

  [[nodiscard]] VelocityCommand command(const Pose2& pose);
  [[nodiscard]] std::size_t target_index() const { return target_; }
  [[nodiscard]] const std::vector<Waypoint>& loop() const { return loop_; }

 private:
  std::vector<Waypoint> loop_;
  double cruise_speed_;
  double lookahead_;
  std::size_t target_ = 0;
};

}  // namespace strata::sim

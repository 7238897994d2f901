#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/navigation/drive_command.hpp"

namespace strata {

struct PurePursuitConfig {
  double lookahead = 0.6;       ///< metres ahead along the path to steer for
  double cruise_speed = 0.6;    ///< m/s on straight stretches
  double min_speed = 0.1;       ///< m/s: slower than this the base barely moves
  double max_turn_rate = 1.0;   ///< rad/s
  double turn_in_place = 0.6;   ///< rad: a larger heading error is turned away on the spot first
  double slow_down = 1.0;       ///< metres before the goal where the speed starts to fall
  double goal_tolerance = 0.2;  ///< metres: closer than this to the last point is arrived
  double turn_gain = 1.5;       ///< rad/s per rad of heading error when turning on the spot
};

/// Pure pursuit (Coulter 1992) for a differential-drive base: steers along the arc through a point one
/// lookahead distance ahead on the path. Slows for sharp arcs and near the goal, turns on the spot when
/// the path lies far off its heading (as a wheelchair does in doorways), and stops at the goal.
/// Remembers how far along the path the robot is, so a path that passes over or under itself (a bridge)
/// is followed in order.
class PurePursuit {
 public:
  explicit PurePursuit(PurePursuitConfig config = {});

  /// A new path (map frame, z the surface height) to follow from its start.
  void set_path(std::vector<Eigen::Vector3d> path);
  void clear();

  struct Output {
    DriveCommand command;
    bool arrived = false;    ///< within the goal tolerance: the command is a stop
    double remaining = 0.0;  ///< metres along the path to its end
  };
  /// The command for the robot at `pose` (z: the height of the ground it stands on).
  [[nodiscard]] Output update(const Pose3& pose);

  [[nodiscard]] bool has_path() const { return !path_.empty(); }
  [[nodiscard]] const PurePursuitConfig& config() const { return config_; }

 private:
  /// Moves progress_ to the path segment nearest the robot, looking only a little ahead of it.
  void advance(const Eigen::Vector3d& position);
  [[nodiscard]] Eigen::Vector2d point_ahead(const Eigen::Vector3d& position, double distance) const;

  PurePursuitConfig config_;
  std::vector<Eigen::Vector3d> path_;
  std::vector<double> along_;  ///< metres from the start to each point, in the plane
  std::size_t progress_ = 0;   ///< index of the segment the robot is on
  double progress_along_ = 0.0;
};

}  // namespace strata

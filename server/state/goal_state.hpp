#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace strata {

/// A goal's life (docs/architecture.md 4.4): accepted -> planning -> driving -> reached | failed | cancelled.
enum class GoalPhase { kAccepted, kPlanning, kDriving, kReached, kFailed, kCancelled };

[[nodiscard]] inline const char* to_string(GoalPhase phase) {
  switch (phase) {
    case GoalPhase::kAccepted:
      return "accepted";
    case GoalPhase::kPlanning:
      return "planning";
    case GoalPhase::kDriving:
      return "driving";
    case GoalPhase::kReached:
      return "reached";
    case GoalPhase::kFailed:
      return "failed";
    case GoalPhase::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

/// Where an operator wants the robot: x, y on the map, and which level by a height (z) near the surface.
/// Without z the goal is on the level whose surface is nearest the robot's own height.
struct GoalRequest {
  double x = 0.0;
  double y = 0.0;
  std::optional<double> z;
};

/// The current (or last) goal, as the goal stream and GET /api/v1/goal report it.
struct GoalStatus {
  std::uint64_t id = 0;  ///< 0: there has never been a goal
  GoalRequest target;
  GoalPhase phase = GoalPhase::kCancelled;
  /// For failed, a code for programs: "goal_not_drivable" (the goal spot is a wall, a step, too narrow),
  /// "off_map" (never seen), "no_connection" (no drivable way there), "blocked" (the way was closed while
  /// driving), "robot_off_map", "stuck", "no_map"; for cancelled, when not by a command:
  /// "operator_disconnected" (the operator connection that set the goal closed); else empty.
  std::string reason;
  /// The same in words for people, as the log says it (for goal_not_drivable with the nearest place the
  /// robot can reach); empty when `reason` is.
  std::string message;
  /// For goal_not_drivable: the nearest place the robot can reach, which the UI offers as a goal one tap
  /// away (the message says it in words).
  std::optional<Eigen::Vector3d> nearest_reachable;
  double stamp = 0.0;  ///< simulated/robot seconds when the phase last changed
};

/// The path being driven, map frame, start to goal; z is the surface height of each point.
struct PlannedPath {
  std::uint64_t goal_id = 0;
  std::uint64_t version = 0;  ///< increments with every (re)plan
  std::vector<Eigen::Vector3d> points;
  double length = 0.0;  ///< metres
};

}  // namespace strata

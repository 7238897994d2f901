#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "core/navigation/patch_graph.hpp"

namespace strata {

/// Why there is no path on the patch graph, or that there is one.
enum class PatchPlanStatus {
  found,
  start_off_map,  ///< no traversable patch under or near the robot
  goal_off_map,   ///< the goal's cell was never seen
  goal_blocked,   ///< the goal's cell has no drivable patch at that level with room for the robot
  no_path,        ///< both ends fine, nothing connects them
};
[[nodiscard]] std::string_view describe(PatchPlanStatus status);

struct PatchPath {
  PatchPlanStatus status = PatchPlanStatus::no_path;
  std::vector<Eigen::Vector3d> points;  ///< cell centres at their surface heights, start to goal
  double length = 0.0;                  ///< metres, in the plane
  std::size_t expanded = 0;
  /// Where the path ends when the goal was moved to a place with room (PatchGoal::room_search_radius).
  std::optional<Eigen::Vector3d> moved_goal;
  [[nodiscard]] bool found() const { return status == PatchPlanStatus::found; }
};

/// Where to go: (x, y) and, if given, the height of the level (within `level_tolerance`); without it the
/// robot's own level, or else the level nearest it (a bridge deck seen from the road under it).
struct PatchGoal {
  double x = 0.0;
  double y = 0.0;
  std::optional<double> z;
  double level_tolerance = 0.5;
  /// A goal where nothing was seen at its level (between a scanner's rings; under a ceiling seen from
  /// below) goes to the nearest drivable patch of that level within this, metres. A goal on something seen
  /// at its level (a wall) is never moved.
  double unseen_search_radius = 0.3;
  /// A goal on drivable ground too near an edge for the robot (beside a wall or a shelf) goes to the
  /// nearest place with room within this, metres (0: refused). A finger on a touch screen is that coarse,
  /// and a wall in the live map stands a cell or two nearer than in the world. A goal on something that is
  /// no ground at its level (a wall's face, a step) is never moved.
  double room_search_radius = 0.0;
};

/// Shortest path (A*, steps of 1 and sqrt 2 cells, octile heuristic: optimal; with a clearance weight,
/// optimal for the length weighted by the closeness to edges) across levels from the
/// patch the robot stands on (`robot_ground`: the map-frame point under it) to the goal's patch. Only
/// patches with room for the robot are entered, except that a robot which already stands too near an edge
/// may drive away from it (to patches of growing clearance) until it has room.
[[nodiscard]] PatchPath plan_on_patches(const PatchGraph& graph, const Eigen::Vector3d& robot_ground,
                                        const PatchGoal& goal);

/// Where to send the robot instead of a goal that is no place for it (a wall, a step, too near an edge):
/// the nearest patch within `radius` metres of (x, y) in the plane, near the goal's level, with room for the
/// robot and connected to the patch it stands on. None when there is none or the robot has no room itself.
[[nodiscard]] std::optional<Eigen::Vector3d> nearest_reachable(const PatchGraph& graph,
                                                               const Eigen::Vector3d& robot_ground,
                                                               const PatchGoal& goal, double radius);

}  // namespace strata

#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "core/planning/astar.hpp"
#include "core/planning/connected_regions.hpp"
#include "core/planning/cost_field.hpp"
#include "core/planning/jump_point_search.hpp"
#include "core/planning/occupancy_grid.hpp"
#include "core/planning/traversable_grid.hpp"

namespace strata {

struct GridPlannerOptions {
  double robot_radius = 0.0;       ///< metres; cells whose centre is this close to an obstacle are blocked
  bool unknown_is_blocked = true;  ///< unknown cells are obstacles (and inflated) unless false
};

/// How plan() searches: jump point search (the default: the fastest single query) or plain A* (expands
/// every cell it touches; kept as the reference). Both are exact and return the same length.
enum class SearchMethod { jump_point, astar };

/// Why a plan has no path, or that it has one.
enum class PlanStatus { found, start_outside, goal_outside, start_blocked, goal_blocked, no_path };
[[nodiscard]] std::string_view describe(PlanStatus status);

/// A planned path in cells, from start to goal.
struct GridPath {
  PlanStatus status = PlanStatus::no_path;
  std::vector<GridCell> cells;
  double length = 0.0;       ///< cells (multiply by the resolution for metres)
  std::size_t expanded = 0;  ///< cells the search expanded (jump points for jump point search)
  double seconds = 0.0;      ///< search and path extraction
  [[nodiscard]] bool found() const { return status == PlanStatus::found; }
};

/// Plans on one occupancy grid: inflates it by the robot radius and labels its regions once, then answers
/// queries. plan() runs jump point search or A* (one query; they reuse their memory, hence not const: one
/// query at a time per planner); wavefront() gives the goal's whole cost field, from which follow() extracts
/// the path from any start (the same optimal length).
class GridPlanner {
 public:
  GridPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options = {});

  [[nodiscard]] GridPath plan(GridCell start, GridCell goal, SearchMethod method = SearchMethod::jump_point);
  /// Impassable or outside goal: a field that reaches nothing.
  [[nodiscard]] CostField wavefront(GridCell goal) const;
  /// The path from start down a wavefront field to its goal (status says why not, if there is none).
  [[nodiscard]] GridPath follow(const CostField& field, GridCell start) const;

  [[nodiscard]] const TraversableGrid& traversable() const { return traversable_; }
  [[nodiscard]] const ConnectedRegions& regions() const { return regions_; }
  [[nodiscard]] double preparation_seconds() const { return preparation_seconds_; }

 private:
  /// found if a path may exist (both ends inside, passable, in one region), else why not.
  [[nodiscard]] PlanStatus check(GridCell start, GridCell goal) const;

  TraversableGrid traversable_;
  ConnectedRegions regions_;
  JumpPointSearch jump_point_search_;
  AStarSearch astar_search_;
  double preparation_seconds_ = 0.0;
};

}  // namespace strata

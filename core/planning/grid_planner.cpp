#include "core/planning/grid_planner.hpp"

#include <chrono>
#include <utility>

#include "core/planning/astar.hpp"
#include "core/planning/obstacle_inflation.hpp"
#include "core/planning/wavefront.hpp"

namespace strata {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

std::string_view describe(PlanStatus status) {
  switch (status) {
    case PlanStatus::found:
      return "path found";
    case PlanStatus::start_outside:
      return "the start is outside the map";
    case PlanStatus::goal_outside:
      return "the goal is outside the map";
    case PlanStatus::start_blocked:
      return "the start is blocked (an obstacle, unknown, or within the robot radius of an obstacle)";
    case PlanStatus::goal_blocked:
      return "the goal is blocked (an obstacle, unknown, or within the robot radius of an obstacle)";
    case PlanStatus::no_path:
      return "no path: the goal is not connected to the start";
  }
  return "unknown status";
}

GridPlanner::GridPlanner(const OccupancyGrid& grid, const GridPlannerOptions& options) {
  const Clock::time_point begin = Clock::now();
  traversable_ = TraversableGrid(grid.width, grid.height,
                                 inflate_obstacles(grid, options.robot_radius, options.unknown_is_blocked));
  regions_ = ConnectedRegions(traversable_);
  preparation_seconds_ = seconds_since(begin);
}

PlanStatus GridPlanner::check(GridCell start, GridCell goal) const {
  if (!traversable_.contains(start))
    return PlanStatus::start_outside;
  if (!traversable_.contains(goal))
    return PlanStatus::goal_outside;
  if (!traversable_.passable(start))
    return PlanStatus::start_blocked;
  if (!traversable_.passable(goal))
    return PlanStatus::goal_blocked;
  if (regions_.region(traversable_, start) != regions_.region(traversable_, goal))
    return PlanStatus::no_path;
  return PlanStatus::found;
}

GridPath GridPlanner::plan(GridCell start, GridCell goal, SearchMethod method) {
  const Clock::time_point begin = Clock::now();
  GridPath path;
  path.status = check(start, goal);
  if (path.found()) {
    if (method == SearchMethod::jump_point) {
      JumpPointSearch::Result found = jump_point_search_.run(traversable_, start, goal);
      path.expanded = found.expanded;
      path.cells = std::move(found.cells);
    } else {
      AStarSearch::Result found = astar_search_.run(traversable_, start, goal);
      path.expanded = found.expanded;
      path.cells = std::move(found.cells);
    }
    path.length = path_length(path.cells);
    if (path.cells.empty())
      path.status = PlanStatus::no_path;  // regions said connected; kept as a guard, never expected
  }
  path.seconds = seconds_since(begin);
  return path;
}

CostField GridPlanner::wavefront(GridCell goal) const {
  return strata::wavefront(traversable_, goal);
}

GridPath GridPlanner::follow(const CostField& field, GridCell start) const {
  const Clock::time_point begin = Clock::now();
  GridPath path;
  path.status = check(start, field.source);
  path.expanded = field.expanded;
  if (path.found()) {
    path.cells = descend(traversable_, field, start);
    path.length = path_length(path.cells);
    if (path.cells.empty())
      path.status = PlanStatus::no_path;
  }
  path.seconds = seconds_since(begin);
  return path;
}

}  // namespace strata

#pragma once

#include "core/planning/cost_field.hpp"
#include "core/planning/traversable_grid.hpp"

namespace strata {

/// A* from start to goal with the octile heuristic (consistent for these moves, so the result is optimal
/// and no cell is expanded twice); among equal f it expands the deeper cell first, which on open ground
/// walks straight to the goal instead of flooding the ties. Stops when the goal is expanded. The field holds
/// the cost from the start (exact for the expanded cells): descend(grid, field, goal) is the path reversed.
/// Unreached goal: field.at(grid, goal) is infinite.
[[nodiscard]] CostField astar(const TraversableGrid& grid, GridCell start, GridCell goal);

}  // namespace strata

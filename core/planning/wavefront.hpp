#pragma once

#include "core/planning/cost_field.hpp"
#include "core/planning/traversable_grid.hpp"

namespace strata {

/// The thesis's wavefront planner made exact: Dijkstra from the goal outward over every cell reachable from
/// it, giving the optimal path cost from each of them to the goal. descend() from any start then yields an
/// optimal path, which makes it the field for a follower that replans from wherever the robot is.
/// An impassable goal gives a field that reaches nothing.
[[nodiscard]] CostField wavefront(const TraversableGrid& grid, GridCell goal);

}  // namespace strata

#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "core/planning/traversable_grid.hpp"

namespace strata {

/// Path cost (cells) from a search's source to every cell it closed, per slot of its TraversableGrid;
/// infinity where the search did not reach. The wavefront's field (source = goal) is complete: any start in
/// the goal's region descends to the goal without searching again.
struct CostField {
  static constexpr double kUnreached = std::numeric_limits<double>::infinity();

  GridCell source;
  std::vector<double> cost;
  std::size_t expanded = 0;  ///< cells closed by the search

  [[nodiscard]] double at(const TraversableGrid& grid, GridCell c) const {
    return grid.contains(c) ? cost[static_cast<std::size_t>(grid.slot(c))] : kUnreached;
  }
};

/// The path from `from` to the field's source by steepest descent: each step goes to the allowed neighbour n
/// minimising cost(n) + step cost, which on an exact Dijkstra/A* field equals cost(here), so the path is
/// optimal and its length is cost(from). Cells from `from` to the source; empty if `from` was not reached.
[[nodiscard]] std::vector<GridCell> descend(const TraversableGrid& grid, const CostField& field,
                                            GridCell from);

/// Sum of the step costs (1 or sqrt 2) along a path of adjacent cells.
[[nodiscard]] double path_length(const std::vector<GridCell>& cells);

}  // namespace strata

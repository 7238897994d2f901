#pragma once

#include <cstddef>
#include <vector>

#include "core/planning/cost_field.hpp"
#include "core/planning/open_list.hpp"
#include "core/planning/traversable_grid.hpp"

namespace strata {

/// A* from start to goal with the octile heuristic (consistent for these moves, so the result is optimal
/// and no cell is expanded twice); among equal f it expands the deeper cell first, which on open ground
/// walks straight to the goal instead of flooding the ties. Stops when the goal is expanded.
///
/// The search keeps its memory between queries on grids of one size: only the cells a query reached are
/// reset afterwards, so a short query costs what it expands rather than the map's size. One query at a time.
class AStarSearch {
 public:
  struct Result {
    std::vector<GridCell> cells;  ///< start to goal; empty if the goal cannot be reached
    std::size_t expanded = 0;
  };

  [[nodiscard]] Result run(const TraversableGrid& grid, GridCell start, GridCell goal);

 private:
  CostField field_;           ///< cost from the start; infinite everywhere between queries
  std::vector<int> reached_;  ///< slots given a finite cost by the current query
  OpenList open_;
};

}  // namespace strata

#pragma once

#include <cstddef>
#include <vector>

#include "core/planning/open_list.hpp"
#include "core/planning/traversable_grid.hpp"

namespace strata {

/// Jump point search (Harabor and Grastien, AAAI 2011; the no-corner-cutting rules of their ICAPS 2014
/// paper): A* with the octile heuristic that, instead of pushing every neighbour, scans straight and
/// diagonal lines and pushes only the cells where an optimal path may turn (jump points). Among paths of
/// equal length it keeps only the canonical one (diagonal moves first), so it returns the same optimal
/// length as A* while touching far fewer cells on open ground and in rooms.
///
///   Straight move into n (from p = n - step): n is a jump point when a side cell s = n + side is free but
///   the cell beside p (s - step) is blocked: p could not reach s (or n + step + side) diagonally, so the
///   turn must happen at n. A diagonal move has no such cells without corner cutting; n is a jump point when
///   a straight scan from it finds one.
///
/// Memory is kept between queries on grids of one size; only the cells a query reached are reset. One query
/// at a time.
class JumpPointSearch {
 public:
  struct Result {
    std::vector<GridCell> cells;  ///< start to goal, every cell; empty if the goal cannot be reached
    std::size_t expanded = 0;     ///< jump points expanded
  };

  [[nodiscard]] Result run(const TraversableGrid& grid, GridCell start, GridCell goal);

 private:
  std::vector<double> cost_;  ///< per slot: cost from the start of a jump point; infinite elsewhere
  std::vector<int> parent_;   ///< per slot: the jump point it was reached from
  std::vector<int> reached_;  ///< slots given a finite cost by the current query
  OpenList open_;
};

}  // namespace strata

#include "core/planning/cost_field.hpp"

#include <cstdlib>
#include <stdexcept>

namespace strata {

std::vector<GridCell> descend(const TraversableGrid& grid, const CostField& field, GridCell from) {
  std::vector<GridCell> cells;
  if (!(field.at(grid, from) < CostField::kUnreached))
    return cells;
  int here = grid.slot(from);
  cells.push_back(from);
  while (field.cost[static_cast<std::size_t>(here)] > 0.0) {
    const double cost_here = field.cost[static_cast<std::size_t>(here)];
    int best = -1;
    double best_cost = CostField::kUnreached;
    for (const TraversableGrid::Move& move : grid.moves()) {
      if (!grid.allows(here, move))
        continue;
      const double via = field.cost[static_cast<std::size_t>(here + move.offset)] + move.cost;
      if (via < best_cost) {
        best_cost = via;
        best = here + move.offset;
      }
    }
    // Moves are symmetric, so the predecessor that set cost(here) is always a candidate; anything else means
    // the field was not made on this grid.
    if (best < 0 || !(field.cost[static_cast<std::size_t>(best)] < cost_here) || best_cost > cost_here + 1e-6)
      throw std::logic_error("descend: the cost field does not belong to this grid");
    here = best;
    cells.push_back(grid.cell(here));
  }
  return cells;
}

double path_length(const std::vector<GridCell>& cells) {
  double length = 0.0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    const bool diagonal = cells[i].x != cells[i - 1].x && cells[i].y != cells[i - 1].y;
    length += diagonal ? kSqrt2 : 1.0;
  }
  return length;
}

}  // namespace strata

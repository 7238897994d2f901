#include "core/planning/wavefront.hpp"

#include "core/planning/open_list.hpp"

namespace strata {

CostField wavefront(const TraversableGrid& grid, GridCell goal) {
  CostField field;
  field.source = goal;
  field.cost.assign(static_cast<std::size_t>(grid.slot_count()), CostField::kUnreached);
  if (!grid.passable(goal))
    return field;
  double* cost = field.cost.data();
  OpenList open;
  open.reserve(static_cast<std::size_t>(grid.width()) + static_cast<std::size_t>(grid.height()));
  cost[grid.slot(goal)] = 0.0;
  open.push(0.0, 0.0, grid.slot(goal));
  while (!open.empty()) {
    const OpenList::Entry top = open.pop();
    if (top.key > cost[top.slot])
      continue;  // stale: the slot was reached more cheaply since this entry was pushed
    ++field.expanded;
    for (const TraversableGrid::Move& move : grid.moves()) {
      if (!grid.allows(top.slot, move))
        continue;
      const int next = top.slot + move.offset;
      const double via = top.key + move.cost;
      if (via < cost[next]) {
        cost[next] = via;
        open.push(via, 0.0, next);
      }
    }
  }
  return field;
}

}  // namespace strata

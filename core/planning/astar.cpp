#include "core/planning/astar.hpp"

#include "core/planning/open_list.hpp"

namespace strata {

CostField astar(const TraversableGrid& grid, GridCell start, GridCell goal) {
  CostField field;
  field.source = start;
  field.cost.assign(static_cast<std::size_t>(grid.slot_count()), CostField::kUnreached);
  if (!grid.passable(start) || !grid.passable(goal))
    return field;
  double* cost = field.cost.data();
  const int goal_slot = grid.slot(goal);
  OpenList open;
  open.reserve(static_cast<std::size_t>(grid.width()) + static_cast<std::size_t>(grid.height()));
  cost[grid.slot(start)] = 0.0;
  open.push(octile_distance(start, goal), 0.0, grid.slot(start));
  while (!open.empty()) {
    const OpenList::Entry top = open.pop();
    const double g = -top.tie;
    if (g > cost[top.slot])
      continue;  // stale entry
    ++field.expanded;
    if (top.slot == goal_slot)
      break;
    for (const TraversableGrid::Move& move : grid.moves()) {
      if (!grid.allows(top.slot, move))
        continue;
      const int next = top.slot + move.offset;
      const double via = g + move.cost;
      if (via < cost[next]) {
        cost[next] = via;
        open.push(via + octile_distance(grid.cell(next), goal), -via, next);
      }
    }
  }
  return field;
}

}  // namespace strata

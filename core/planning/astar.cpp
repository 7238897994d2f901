#include "core/planning/astar.hpp"

#include <algorithm>

namespace strata {

AStarSearch::Result AStarSearch::run(const TraversableGrid& grid, GridCell start, GridCell goal) {
  Result result;
  if (!grid.passable(start) || !grid.passable(goal))
    return result;
  const std::size_t slots = static_cast<std::size_t>(grid.slot_count());
  if (field_.cost.size() != slots)
    field_.cost.assign(slots, CostField::kUnreached);
  field_.source = start;
  double* cost = field_.cost.data();
  const int goal_slot = grid.slot(goal);
  const int stride = grid.width() + 2;
  const auto heuristic = [&](int x, int y) {  // octile distance to the goal
    const int dx = x > goal.x ? x - goal.x : goal.x - x;
    const int dy = y > goal.y ? y - goal.y : goal.y - y;
    return dx < dy ? dy + (kSqrt2 - 1.0) * dx : dx + (kSqrt2 - 1.0) * dy;
  };
  const int start_slot = grid.slot(start);
  cost[start_slot] = 0.0;
  reached_.push_back(start_slot);
  open_.push(heuristic(start.x, start.y), 0.0, start_slot);
  while (!open_.empty()) {
    const OpenList::Entry top = open_.pop();
    const double g = -top.tie;
    if (g > cost[top.slot])
      continue;  // stale entry
    ++result.expanded;
    if (top.slot == goal_slot)
      break;
    const int x = top.slot % stride - 1;
    const int y = top.slot / stride - 1;
    for (const TraversableGrid::Move& move : grid.moves()) {
      if (!grid.allows(top.slot, move))
        continue;
      const int next = top.slot + move.offset;
      const double via = g + move.cost;
      if (via < cost[next]) {
        if (cost[next] == CostField::kUnreached)
          reached_.push_back(next);
        cost[next] = via;
        open_.push(via + heuristic(x + move.dx, y + move.dy), -via, next);
      }
    }
  }
  result.cells = descend(grid, field_, goal);
  std::reverse(result.cells.begin(), result.cells.end());
  for (const int slot : reached_)
    cost[slot] = CostField::kUnreached;
  reached_.clear();
  open_.clear();
  return result;
}

}  // namespace strata

#include "core/planning/jump_point_search.hpp"

#include <algorithm>
#include <limits>

namespace strata {
namespace {

constexpr double kUnreached = std::numeric_limits<double>::infinity();

/// Scans from `slot` along a straight `step`; `side` is the perpendicular slot offset. Returns the first
/// jump point (the goal, or a cell with a forced turn) or -1 when the scan runs into an obstacle.
int jump_straight(const TraversableGrid& grid, int slot, int step, int side, int goal) {
  for (;; slot += step) {
    if (!grid.passable_slot(slot))
      return -1;
    if (slot == goal)
      return slot;
    if ((grid.passable_slot(slot + side) && !grid.passable_slot(slot + side - step)) ||
        (grid.passable_slot(slot - side) && !grid.passable_slot(slot - side - step)))
      return slot;
  }
}

/// Scans from `slot` (entered by a legal diagonal move) along the diagonal step_x + step_y. A cell is a jump
/// point if it is the goal or a straight scan from it along step_x or step_y finds one. -1 when the
/// diagonal is blocked (either orthogonal cell blocked too: no corner cutting).
int jump_diagonal(const TraversableGrid& grid, int slot, int step_x, int step_y, int stride, int goal) {
  for (;;) {
    if (slot == goal || jump_straight(grid, slot + step_x, step_x, stride, goal) >= 0 ||
        jump_straight(grid, slot + step_y, step_y, 1, goal) >= 0)
      return slot;
    if (!grid.passable_slot(slot + step_x) || !grid.passable_slot(slot + step_y) ||
        !grid.passable_slot(slot + step_x + step_y))
      return -1;
    slot += step_x + step_y;
  }
}

int sign(int v) {
  return (v > 0) - (v < 0);
}

}  // namespace

JumpPointSearch::Result JumpPointSearch::run(const TraversableGrid& grid, GridCell start, GridCell goal) {
  Result result;
  if (!grid.passable(start) || !grid.passable(goal))
    return result;
  const std::size_t slots = static_cast<std::size_t>(grid.slot_count());
  if (cost_.size() != slots) {
    cost_.assign(slots, kUnreached);
    parent_.assign(slots, -1);
  }
  const int stride = grid.width() + 2;
  const int start_slot = grid.slot(start);
  const int goal_slot = grid.slot(goal);
  const auto heuristic = [&](GridCell c) { return octile_distance(c, goal); };

  // Pushes jump point `next` reached from `from` (a straight or diagonal segment: its length is octile).
  const auto reach = [&](int from, GridCell from_cell, double g, int next) {
    if (next < 0)
      return;
    const GridCell cell = grid.cell(next);
    const double via = g + octile_distance(from_cell, cell);
    if (via < cost_[static_cast<std::size_t>(next)]) {
      if (cost_[static_cast<std::size_t>(next)] == kUnreached)
        reached_.push_back(next);
      cost_[static_cast<std::size_t>(next)] = via;
      parent_[static_cast<std::size_t>(next)] = from;
      open_.push(via + heuristic(cell), -via, next);
    }
  };
  // Scans from n in direction (dx, dy) (dx, dy in -1..1) for the next jump point.
  const auto scan = [&](int n, int dx, int dy) {
    if (dx != 0 && dy != 0) {
      const int next = n + dx + dy * stride;
      if (!grid.passable_slot(n + dx) || !grid.passable_slot(n + dy * stride) || !grid.passable_slot(next))
        return -1;
      return jump_diagonal(grid, next, dx, dy * stride, stride, goal_slot);
    }
    const int step = dx + dy * stride;
    return jump_straight(grid, n + step, step, dx != 0 ? stride : 1, goal_slot);
  };

  cost_[static_cast<std::size_t>(start_slot)] = 0.0;
  parent_[static_cast<std::size_t>(start_slot)] = -1;
  reached_.push_back(start_slot);
  open_.push(heuristic(start), 0.0, start_slot);
  bool found = false;
  while (!open_.empty()) {
    const OpenList::Entry top = open_.pop();
    const double g = -top.tie;
    const int n = top.slot;
    if (g > cost_[static_cast<std::size_t>(n)])
      continue;  // stale entry
    ++result.expanded;
    if (n == goal_slot) {
      found = true;
      break;
    }
    const GridCell cell = grid.cell(n);
    const int parent = parent_[static_cast<std::size_t>(n)];
    if (parent < 0) {  // the start: every direction
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx != 0 || dy != 0)
            reach(n, cell, g, scan(n, dx, dy));
      continue;
    }
    const GridCell from = grid.cell(parent);
    const int dx = sign(cell.x - from.x);
    const int dy = sign(cell.y - from.y);
    if (dx != 0 && dy != 0) {  // diagonal: the two straight scans and the diagonal onward
      reach(n, cell, g, scan(n, dx, 0));
      reach(n, cell, g, scan(n, 0, dy));
      reach(n, cell, g, scan(n, dx, dy));
      continue;
    }
    // Straight: onward, and for each side whose cell beside the parent is blocked, the turn (straight to
    // the side and diagonal forward to it).
    const int step = dx + dy * stride;
    reach(n, cell, g, scan(n, dx, dy));
    for (const int side_sign : {-1, 1}) {
      const int side = side_sign * (dx != 0 ? stride : 1);
      if (!grid.passable_slot(n + side) || grid.passable_slot(n + side - step))
        continue;
      const int side_dx = dx != 0 ? 0 : side_sign;
      const int side_dy = dx != 0 ? side_sign : 0;
      reach(n, cell, g, scan(n, side_dx, side_dy));
      reach(n, cell, g, scan(n, dx + side_dx, dy + side_dy));
    }
  }

  if (found) {
    std::vector<int> jump_points;
    for (int slot = goal_slot; slot >= 0; slot = parent_[static_cast<std::size_t>(slot)])
      jump_points.push_back(slot);
    std::reverse(jump_points.begin(), jump_points.end());
    result.cells.push_back(grid.cell(jump_points.front()));
    for (std::size_t i = 1; i < jump_points.size(); ++i) {
      const GridCell to = grid.cell(jump_points[i]);
      GridCell at = result.cells.back();
      const int step_x = sign(to.x - at.x);
      const int step_y = sign(to.y - at.y);
      while (!(at == to)) {
        at = {at.x + step_x, at.y + step_y};
        result.cells.push_back(at);
      }
    }
  }
  for (const int slot : reached_)
    cost_[static_cast<std::size_t>(slot)] = kUnreached;
  reached_.clear();
  open_.clear();
  return result;
}

}  // namespace strata

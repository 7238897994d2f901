#include "core/planning/connected_regions.hpp"

namespace strata {

ConnectedRegions::ConnectedRegions(const TraversableGrid& grid)
    : labels_(static_cast<std::size_t>(grid.slot_count()), kBlocked) {
  std::vector<int> stack;
  const auto& moves = grid.moves();
  for (int seed = 0; seed < grid.slot_count(); ++seed) {
    if (!grid.passable_slot(seed) || labels_[static_cast<std::size_t>(seed)] != kBlocked)
      continue;
    const int label = count_++;
    labels_[static_cast<std::size_t>(seed)] = label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int here = stack.back();
      stack.pop_back();
      for (int m = 0; m < 4; ++m) {  // the four straight moves come first
        const int next = here + moves[static_cast<std::size_t>(m)].offset;
        if (grid.passable_slot(next) && labels_[static_cast<std::size_t>(next)] == kBlocked) {
          labels_[static_cast<std::size_t>(next)] = label;
          stack.push_back(next);
        }
      }
    }
  }
}

}  // namespace strata

#pragma once

#include <vector>

#include "core/planning/traversable_grid.hpp"

namespace strata {

/// Labels the passable cells by region: two cells share a label exactly when a path joins them. Without
/// corner cutting a diagonal move needs both orthogonal cells free, so it can always be replaced by two
/// straight ones: reachability is plain 4-connectivity. One O(cells) pass per map; afterwards a goal in
/// another region is rejected in O(1) instead of by searching the start's whole region.
class ConnectedRegions {
 public:
  static constexpr int kBlocked = -1;

  ConnectedRegions() = default;
  explicit ConnectedRegions(const TraversableGrid& grid);

  /// The region of a cell (kBlocked for impassable or outside cells).
  [[nodiscard]] int region(const TraversableGrid& grid, GridCell c) const {
    return grid.contains(c) ? labels_[static_cast<std::size_t>(grid.slot(c))] : kBlocked;
  }
  [[nodiscard]] int count() const { return count_; }

 private:
  std::vector<int> labels_;  ///< per slot
  int count_ = 0;
};

}  // namespace strata

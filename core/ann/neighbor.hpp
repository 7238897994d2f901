#pragma once

#include <cstddef>
#include <optional>

namespace strata {

/// A point found by a nearest-neighbour search: its index in the searched cloud and its squared distance
/// to the query.
struct Neighbor {
  std::size_t index = 0;
  double squared_distance = 0.0;
};

/// The closest point to a query and the next closest, within a search bound.
struct NearestTwo {
  std::optional<Neighbor> first;
  std::optional<Neighbor> second;  ///< empty when at most one point lies within the bound
};

}  // namespace strata

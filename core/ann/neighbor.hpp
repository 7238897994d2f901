#pragma once

#include <cstddef>

namespace strata {

/// A point found by a nearest-neighbour search: its index in the searched cloud and its squared distance
/// to the query.
struct Neighbor {
  std::size_t index = 0;
  double squared_distance = 0.0;
};

}  // namespace strata

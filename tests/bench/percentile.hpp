#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace strata::bench {

/// The value at `fraction` (0: smallest, 1: largest) of `values`, the nearest rank; -1 when there are none.
inline double percentile(std::vector<double> values, double fraction) {
  if (values.empty())
    return -1.0;
  std::sort(values.begin(), values.end());
  const auto index = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(index, values.size() - 1)];
}

}  // namespace strata::bench

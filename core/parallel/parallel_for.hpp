#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace strata {

/// Runs `chunk(begin, end)` over [0, count) split into at most `threads` contiguous parts, the first on
/// the calling thread, and returns when all are done. Fewer parts where a part would get fewer than
/// `min_per_part` items: a thread's start and join cost about 30 microseconds here. The parts must write
/// to disjoint memory; each part's range is the same whatever the machine, so results that depend only on
/// the items do not change with `threads`.
template <class Chunk>
void parallel_for(std::size_t count, unsigned threads, std::size_t min_per_part, Chunk&& chunk) {
  const std::size_t parts =
      std::clamp<std::size_t>(count / std::max<std::size_t>(min_per_part, 1), 1, std::max(threads, 1U));
  std::vector<std::jthread> helpers;
  helpers.reserve(parts - 1);
  for (std::size_t k = 1; k < parts; ++k)
    helpers.emplace_back([&chunk, k, count, parts] { chunk(k * count / parts, (k + 1) * count / parts); });
  chunk(std::size_t{0}, count / parts);
}  // the helpers join as they leave scope

}  // namespace strata

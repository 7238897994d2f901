#include "core/planning/traversable_grid.hpp"

#include <stdexcept>

namespace strata {

TraversableGrid::TraversableGrid(int width, int height, const std::vector<std::uint8_t>& blocked)
    : width_(width), height_(height), stride_(width + 2) {
  if (width < 0 || height < 0 ||
      blocked.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("TraversableGrid: blocked flags do not match the grid size");
  if ((static_cast<double>(width) + 2.0) * (static_cast<double>(height) + 2.0) > 2147483647.0)
    throw std::invalid_argument("TraversableGrid: the grid is too large for int slots");
  passable_.assign(static_cast<std::size_t>(slot_count()), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      passable_[static_cast<std::size_t>(slot({x, y}))] =
          blocked[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)] == 0;
  const int s = stride_;
  moves_ = {{{1, 1.0, 0, 0, 1, 0},
             {-1, 1.0, 0, 0, -1, 0},
             {s, 1.0, 0, 0, 0, 1},
             {-s, 1.0, 0, 0, 0, -1},
             {s + 1, kSqrt2, 1, s, 1, 1},
             {s - 1, kSqrt2, -1, s, -1, 1},
             {-s + 1, kSqrt2, 1, -s, 1, -1},
             {-s - 1, kSqrt2, -1, -s, -1, -1}}};
}

}  // namespace strata

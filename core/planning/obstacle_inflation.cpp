#include "core/planning/obstacle_inflation.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace strata {
namespace {

constexpr double kNoObstacle = std::numeric_limits<double>::infinity();

/// Squared distance (cells) from each cell to the nearest obstacle in its own column, or kNoObstacle.
std::vector<double> column_distances(const std::vector<std::uint8_t>& obstacle, int width, int height) {
  std::vector<double> squared(obstacle.size(), kNoObstacle);
  std::vector<int> down(static_cast<std::size_t>(height));
  const int none = 2 * height + 2;  // farther than any obstacle in the column can be
  for (int x = 0; x < width; ++x) {
    int distance = none;
    for (int y = 0; y < height; ++y) {
      const std::size_t i =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      distance = obstacle[i] != 0 ? 0 : (distance < none ? distance + 1 : none);
      down[static_cast<std::size_t>(y)] = distance;
    }
    distance = none;
    for (int y = height - 1; y >= 0; --y) {
      const std::size_t i =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      distance = obstacle[i] != 0 ? 0 : (distance < none ? distance + 1 : none);
      const int nearest = std::min(distance, down[static_cast<std::size_t>(y)]);
      if (nearest < none)
        squared[i] = static_cast<double>(nearest) * nearest;
    }
  }
  return squared;
}

}  // namespace

std::vector<std::uint8_t> inflate_obstacles(const OccupancyGrid& grid, double robot_radius,
                                            bool unknown_is_blocked) {
  std::vector<std::uint8_t> blocked(grid.cells.size());
  for (std::size_t i = 0; i < grid.cells.size(); ++i)
    blocked[i] =
        grid.cells[i] == CellState::occupied || (unknown_is_blocked && grid.cells[i] == CellState::unknown);
  const double radius_cells = robot_radius / grid.resolution;
  // Cell centres are at least one cell apart: a radius under one cell blocks nothing beyond the obstacles.
  if (!(radius_cells >= 1.0) || grid.cells.empty())
    return blocked;
  // A hair above r^2 so a radius that is an exact multiple of the resolution (0.1 m at 0.05 m) still blocks
  // the cells at exactly that distance despite rounding in the division.
  const double max_squared = radius_cells * radius_cells * (1.0 + 1e-9);

  // Separable exact EDT: column distances, then per row the lower envelope of the parabolas
  // (x - q)^2 + column(q) (Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions", 2012).
  const int width = grid.width;
  const std::vector<double> column = column_distances(blocked, width, grid.height);
  std::vector<int> apex(static_cast<std::size_t>(width));          // q of each parabola in the envelope
  std::vector<double> start(static_cast<std::size_t>(width) + 1);  // where each one begins to be lowest
  for (int y = 0; y < grid.height; ++y) {
    const double* f = column.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    std::uint8_t* row = blocked.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    int k = -1;
    for (int q = 0; q < width; ++q) {
      if (f[q] == kNoObstacle)
        continue;
      double s = -kNoObstacle;
      while (k >= 0) {
        const int p = apex[static_cast<std::size_t>(k)];
        s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
        if (s > start[static_cast<std::size_t>(k)])
          break;
        --k;
        s = -kNoObstacle;
      }
      ++k;
      apex[static_cast<std::size_t>(k)] = q;
      start[static_cast<std::size_t>(k)] = s;
    }
    if (k < 0)
      continue;  // no obstacle in any column of this row's reach
    start[static_cast<std::size_t>(k) + 1] = kNoObstacle;
    int j = 0;
    for (int x = 0; x < width; ++x) {
      while (start[static_cast<std::size_t>(j) + 1] < x)
        ++j;
      const int p = apex[static_cast<std::size_t>(j)];
      const double squared = double(x - p) * (x - p) + f[p];
      if (squared <= max_squared)
        row[x] = 1;
    }
  }
  return blocked;
}

}  // namespace strata

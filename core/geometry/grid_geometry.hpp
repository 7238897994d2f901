#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace strata {

/// A cell of a 2D grid by column (x) and row (y).
struct GridCell {
  int x = 0;
  int y = 0;
  bool operator==(const GridCell&) const = default;
};

/// Where a 2D grid lies in the map frame, shared by every grid (the drivable map's LevelGrid, the planner's
/// OccupancyGrid): cell (x, y) covers [origin + (x, y) * resolution, origin + (x + 1, y + 1) * resolution),
/// row 0 at the lowest y, stored row by row (index y * width + x). A ROS map_server map is the same
/// layout with its image rows flipped.
struct GridGeometry {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< map-frame corner of cell (0, 0), metres
  double resolution = 1.0;                           ///< metres per cell side
  int width = 0;
  int height = 0;

  [[nodiscard]] std::size_t cell_count() const {
    return static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  }
  [[nodiscard]] bool contains(GridCell c) const {
    return c.x >= 0 && c.y >= 0 && c.x < width && c.y < height;
  }
  [[nodiscard]] std::size_t index(GridCell c) const {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c.x);
  }
  /// The cell containing a map-frame point (it may lie outside the grid: check contains()).
  [[nodiscard]] GridCell cell_of(const Eigen::Vector2d& point) const {
    const Eigen::Vector2d local = (point - origin) / resolution;
    // Clamped first: a point far outside (or NaN) stays outside instead of overflowing the int.
    const auto index = [](double v) {
      return std::isnan(v) ? -1 : static_cast<int>(std::clamp(std::floor(v), -1e9, 1e9));
    };
    return {index(local.x()), index(local.y())};
  }
  /// The map-frame centre of a cell.
  [[nodiscard]] Eigen::Vector2d center_of(GridCell c) const {
    return origin + resolution * Eigen::Vector2d(c.x + 0.5, c.y + 0.5);
  }
};

}  // namespace strata

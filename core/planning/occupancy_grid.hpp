#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace strata {

/// What is known about one cell of an occupancy grid.
enum class CellState : std::uint8_t { free, occupied, unknown };

/// A cell of a 2D grid by column (x) and row (y).
struct GridCell {
  int x = 0;
  int y = 0;
  bool operator==(const GridCell&) const = default;
};

/// A 2D occupancy grid. Cell (x, y) covers the square [origin + (x, y) * resolution, origin + (x + 1, y + 1)
/// * resolution) in the map frame (metres); cells are stored row by row, index y * width + x.
struct OccupancyGrid {
  int width = 0;
  int height = 0;
  double resolution = 1.0;                           ///< metres per cell side
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< map-frame corner of cell (0, 0)
  std::vector<CellState> cells;

  OccupancyGrid() = default;
  OccupancyGrid(int width_cells, int height_cells, double resolution_m = 1.0,
                const Eigen::Vector2d& origin_m = Eigen::Vector2d::Zero(), CellState fill = CellState::free)
      : width(width_cells),
        height(height_cells),
        resolution(resolution_m),
        origin(origin_m),
        cells(static_cast<std::size_t>(width_cells) * static_cast<std::size_t>(height_cells), fill) {}

  [[nodiscard]] bool contains(GridCell c) const {
    return c.x >= 0 && c.y >= 0 && c.x < width && c.y < height;
  }
  [[nodiscard]] std::size_t index(GridCell c) const {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c.x);
  }
  [[nodiscard]] CellState at(GridCell c) const { return cells[index(c)]; }
  [[nodiscard]] CellState& at(GridCell c) { return cells[index(c)]; }

  /// The cell containing a map-frame point (it may lie outside the grid: check contains()).
  [[nodiscard]] GridCell cell_of(const Eigen::Vector2d& point) const {
    const Eigen::Vector2d local = (point - origin) / resolution;
    // Clamped first: a point far outside stays outside instead of overflowing the int.
    const auto index = [](double v) { return static_cast<int>(std::clamp(std::floor(v), -1e9, 1e9)); };
    return {index(local.x()), index(local.y())};
  }
  /// The map-frame centre of a cell.
  [[nodiscard]] Eigen::Vector2d center_of(GridCell c) const {
    return origin + resolution * Eigen::Vector2d(c.x + 0.5, c.y + 0.5);
  }
};

}  // namespace strata

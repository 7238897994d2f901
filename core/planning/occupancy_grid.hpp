#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/geometry/grid_geometry.hpp"

namespace strata {

/// What is known about one cell of an occupancy grid.
enum class CellState : std::uint8_t { free, occupied, unknown };

/// A 2D occupancy grid for the grid planners, laid out as every grid is (GridGeometry).
struct OccupancyGrid : GridGeometry {
  std::vector<CellState> cells;  ///< cell_count(), row by row

  OccupancyGrid() = default;
  OccupancyGrid(int width_cells, int height_cells, double resolution_m = 1.0,
                const Eigen::Vector2d& origin_m = Eigen::Vector2d::Zero(), CellState fill = CellState::free)
      : GridGeometry{origin_m, resolution_m, width_cells, height_cells}, cells(cell_count(), fill) {}

  [[nodiscard]] CellState at(GridCell c) const { return cells[index(c)]; }
  [[nodiscard]] CellState& at(GridCell c) { return cells[index(c)]; }
};

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace strata {

/// Per cell, as in ROS nav_msgs/OccupancyGrid.
enum class Occupancy : std::int8_t { unknown = -1, free = 0, occupied = 100 };

/// The occupancy at one level of the MLS map: cell (col, row) covers [origin + (col, row) * resolution,
/// + resolution), row 0 at the lowest y; the UI's occupancy view and, converted, the planner's map. Named
/// apart from planning's OccupancyGrid (no levels): two different types of one name in one namespace
/// break the one-definition rule, which ASan caught as a stack overflow in the grid's destructor.
struct LevelGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< map-frame corner of cell (0, 0), metres
  double resolution = 0.1;
  int width = 0;
  int height = 0;
  std::vector<Occupancy> cells;  ///< row-major, width * height
  /// Height of the surface the robot reaches in each free cell (NaN elsewhere): which level it is.
  std::vector<float> surface_height;

  [[nodiscard]] Occupancy at(int col, int row) const {
    return cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(col)];
  }
  /// The cell containing map-frame (x, y); unknown outside the grid.
  [[nodiscard]] Occupancy at_position(double x, double y) const {
    const auto col = static_cast<int>(std::floor((x - origin.x()) / resolution));
    const auto row = static_cast<int>(std::floor((y - origin.y()) / resolution));
    if (col < 0 || row < 0 || col >= width || row >= height)
      return Occupancy::unknown;
    return at(col, row);
  }
};

}  // namespace strata

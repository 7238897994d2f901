#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry/grid_geometry.hpp"

namespace strata {

/// Per cell, as in ROS nav_msgs/OccupancyGrid.
enum class Occupancy : std::int8_t { unknown = -1, free = 0, occupied = 100 };

/// The occupancy at one level of the MLS map, laid out as every grid is (GridGeometry, at the MLS map's
/// resolution): the UI's occupancy view and the ROS map download. Named apart from planning's
/// OccupancyGrid (no levels): two different types of one name in one namespace break the one-definition
/// rule, which ASan caught as a stack overflow in the grid's destructor.
struct LevelGrid : GridGeometry {
  std::vector<Occupancy> cells;  ///< cell_count(), row by row
  /// Height of the surface the robot reaches in each free cell (NaN elsewhere): which level it is.
  std::vector<float> surface_height;

  [[nodiscard]] Occupancy at(int col, int row) const { return cells[index({col, row})]; }
  /// The cell containing map-frame (x, y); unknown outside the grid.
  [[nodiscard]] Occupancy at_position(double x, double y) const {
    const GridCell cell = cell_of({x, y});
    return contains(cell) ? cells[index(cell)] : Occupancy::unknown;
  }
  /// surface_height of the cell containing map-frame (x, y); NaN outside the grid or where not free.
  [[nodiscard]] float surface_height_at(double x, double y) const {
    const GridCell cell = cell_of({x, y});
    return contains(cell) && index(cell) < surface_height.size() ? surface_height[index(cell)]
                                                                 : std::numeric_limits<float>::quiet_NaN();
  }
};

}  // namespace strata

#pragma once

#include <cstdint>
#include <vector>

#include "core/planning/occupancy_grid.hpp"

namespace strata {

/// Which cells the robot's centre may not occupy: the obstacles (occupied cells, and unknown ones when
/// unknown_is_blocked) and every cell whose centre lies within robot_radius (metres) of an obstacle cell's
/// centre, as ROS costmaps measure the inscribed radius. Returns one flag per cell (1 = blocked), indexed
/// like grid.cells. Exact Euclidean distances (Felzenszwalb-Huttenlocher distance transform), O(cells) for
/// any radius.
[[nodiscard]] std::vector<std::uint8_t> inflate_obstacles(const OccupancyGrid& grid, double robot_radius,
                                                          bool unknown_is_blocked = true);

}  // namespace strata

#include "core/mls/drivable_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace strata {

DrivableMap compute_drivable_map(const MlsMap& map, const TraversabilityConfig& config,
                                 const Eigen::Vector3d& robot_ground, const CellRegion& region) {
  return compute_drivable_map(map, SurfaceGrid(map, region, config), config, robot_ground);
}

DrivableMap compute_drivable_map(const MlsMap& map, const SurfaceGrid& surfaces,
                                 const TraversabilityConfig& config, const Eigen::Vector3d& robot_ground) {
  const CellRegion& region = surfaces.region();
  DrivableMap result;
  LevelGrid& grid = result.grid;
  grid.resolution = map.resolution();
  grid.origin = {region.min.x * map.resolution(), region.min.y * map.resolution()};
  grid.width = std::max(region.width, 0);
  grid.height = std::max(region.height, 0);
  const std::size_t cells = static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height);
  grid.cells.assign(cells, Occupancy::unknown);
  grid.surface_height.assign(cells, std::numeric_limits<float>::quiet_NaN());
  if (cells == 0)
    return result;

  for (std::size_t c = 0; c < cells; ++c)
    if (!surfaces.surfaces(c).empty())
      grid.cells[c] = Occupancy::occupied;  // observed; free only if the fill reaches it

  // The robot's patch: the horizontal patch nearest its ground height in its cell or, since many scanners
  // do not see the ground under the robot, in the nearest ring of cells around it that has one. Any
  // horizontal patch: the robot stands there whatever the classification says.
  const auto [robot_col, robot_row] = surfaces.local(map.cell_of(robot_ground.x(), robot_ground.y()));
  const std::optional<std::uint32_t> start =
      surfaces.nearest_surface(robot_col, robot_row, robot_ground.z(), config.start_tolerance,
                               static_cast<int>(std::ceil(config.start_search_radius / map.resolution())),
                               SurfaceGrid::Standing::kHorizontal);
  if (!start)
    return result;
  result.start_found = true;
  const std::uint32_t start_surface = *start;
  const std::size_t start_cell = surfaces.cell_of_surface(start_surface);
  const int start_col = static_cast<int>(start_cell % static_cast<std::size_t>(region.width));
  const int start_row = static_cast<int>(start_cell / static_cast<std::size_t>(region.width));

  struct Item {
    int col;
    int row;
    float top;
  };
  std::vector<std::uint8_t> reached(surfaces.surface_count(), 0);
  std::vector<Item> stack;
  const auto reach = [&](int col, int row, std::uint32_t surface, float top) {
    reached[surface] = 1;
    const std::size_t c = surfaces.cell(col, row);
    if (grid.cells[c] != Occupancy::free)
      ++result.free_cells;
    grid.cells[c] = Occupancy::free;
    grid.surface_height[c] = top;
    stack.push_back({col, row, top});
  };
  // The robot stands on its patch even if the classification (say, a slope estimate at a map edge) would
  // not enter it.
  reach(start_col, start_row, start_surface, surfaces.surface(start_surface).top);

  constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    for (const auto& offset : kNeighbours) {
      const int col = item.col + offset[0];
      const int row = item.row + offset[1];
      const std::optional<std::uint32_t> next = surfaces.step_onto(col, row, item.top);
      if (next && reached[*next] == 0)
        reach(col, row, *next, surfaces.surface(*next).top);
    }
  }
  return result;
}

CellRegion changed_region(const MlsMap& map, std::uint64_t version, const Eigen::Vector3d& robot_ground) {
  const CellIndex robot = map.cell_of(robot_ground.x(), robot_ground.y());
  return CellRegion::bounding(CellRegion::of_tiles(map.tiles_changed_since(version)),
                              CellRegion::of_tiles({MlsMap::tile_of(robot)}));
}

}  // namespace strata

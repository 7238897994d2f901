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
  // do not see the ground right under the robot, in the nearest ring of cells around it that has one.
  const CellIndex robot = map.cell_of(robot_ground.x(), robot_ground.y());
  const int search = static_cast<int>(std::ceil(config.start_search_radius / map.resolution()));
  int start_col = 0;
  int start_row = 0;
  std::uint32_t start_surface = 0;
  for (int ring = 0; ring <= search && !result.start_found; ++ring) {
    double nearest = config.start_tolerance;
    for (int dy = -ring; dy <= ring; ++dy)
      for (int dx = -ring; dx <= ring; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != ring)
          continue;
        const CellIndex cell{robot.x + dx, robot.y + dy};
        if (!region.contains(cell))
          continue;
        const int col = cell.x - region.min.x;
        const int row = cell.y - region.min.y;
        const std::size_t c = surfaces.cell(col, row);
        const std::span<const SurfaceGrid::Surface> candidates = surfaces.surfaces(c);
        for (std::size_t i = 0; i < candidates.size(); ++i) {
          const double difference = std::abs(static_cast<double>(candidates[i].top) - robot_ground.z());
          if (!candidates[i].vertical && difference <= nearest) {
            nearest = difference;
            start_col = col;
            start_row = row;
            start_surface = surfaces.first_surface(c) + static_cast<std::uint32_t>(i);
            result.start_found = true;
          }
        }
      }
  }
  if (!result.start_found)
    return result;
  const std::size_t start_cell = surfaces.cell(start_col, start_row);

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
  reach(start_col, start_row, start_surface, [&] {
    return surfaces.surfaces(start_cell)[start_surface - surfaces.first_surface(start_cell)].top;
  }());

  const auto max_step = static_cast<float>(config.max_step);
  constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    for (const auto& offset : kNeighbours) {
      const int col = item.col + offset[0];
      const int row = item.row + offset[1];
      if (col < 0 || row < 0 || col >= grid.width || row >= grid.height)
        continue;
      const std::size_t c = surfaces.cell(col, row);
      const std::uint32_t first = surfaces.first_surface(c);
      const std::span<const SurfaceGrid::Surface> candidates = surfaces.surfaces(c);
      // The patch of the neighbour cell this one connects to: the traversable one nearest in height.
      std::uint32_t chosen = 0;
      float best = max_step;
      bool found = false;
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        const float difference = std::abs(candidates[i].top - item.top);
        if (candidates[i].traversable && difference <= best) {
          best = difference;
          chosen = first + static_cast<std::uint32_t>(i);
          found = true;
        }
      }
      if (found && reached[chosen] == 0)
        reach(col, row, chosen, candidates[chosen - first].top);
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

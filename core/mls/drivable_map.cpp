#include "core/mls/drivable_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/mls/unseen_gaps.hpp"

namespace strata {

DrivableMap compute_drivable_map(const MlsMap& map, const TraversabilityConfig& config,
                                 const Eigen::Vector3d& robot_ground, const CellRegion& region) {
  return compute_drivable_map(map, SurfaceGrid(map, region, config), config, robot_ground);
}

namespace {

/// Where the robot's level is around each cell: the height of the nearest ground the fill reached and how
/// far that is, in cells (a breadth-first search from all reached cells at once).
struct NearestLevel {
  std::vector<float> height;
  std::vector<int> distance;  ///< cells; -1 where no ground was reached at all
};

NearestLevel nearest_level(const LevelGrid& grid) {
  NearestLevel level;
  level.height.assign(grid.cells.size(), 0.0F);
  level.distance.assign(grid.cells.size(), -1);
  std::vector<std::size_t> queue;
  queue.reserve(grid.cells.size());
  for (std::size_t c = 0; c < grid.cells.size(); ++c)
    if (grid.cells[c] == Occupancy::free) {
      level.height[c] = grid.surface_height[c];
      level.distance[c] = 0;
      queue.push_back(c);
    }
  const auto width = static_cast<std::size_t>(grid.width);
  for (std::size_t next = 0; next < queue.size(); ++next) {
    const std::size_t c = queue[next];
    const std::size_t col = c % width;
    const auto visit = [&](std::size_t n) {
      if (level.distance[n] >= 0)
        return;
      level.distance[n] = level.distance[c] + 1;
      level.height[n] = level.height[c];
      queue.push_back(n);
    };
    if (col > 0)
      visit(c - 1);
    if (col + 1 < width)
      visit(c + 1);
    if (c >= width)
      visit(c - width);
    if (c + width < grid.cells.size())
      visit(c + width);
  }
  return level;
}

/// The cells the fill did not reach, judged against the level of the nearest reached ground: a surface
/// the robot may not drive (a wall, a steep slope, ground under a low ceiling) or drivable ground higher or
/// lower than the level could climb to over the distance (a step, a stair landing, a drop; the grade the
/// gap inference allows) is an obstacle; other drivable ground is free, connected or not (a ring of floor
/// beyond the last one joined); anything a robot height above the level is overhead (the deck over the
/// road) and says nothing of the level: unknown.
void classify_unreached(const SurfaceGrid& surfaces, const TraversabilityConfig& config, double resolution,
                        LevelGrid& grid) {
  const NearestLevel level = nearest_level(grid);
  const auto reach = static_cast<float>(config.robot_height);
  for (std::size_t c = 0; c < grid.cells.size(); ++c) {
    if (grid.cells[c] == Occupancy::free)
      continue;
    const bool known = level.distance[c] >= 0;
    const float h = level.height[c];
    const auto band = static_cast<float>(config.max_step + std::max(level.distance[c], 0) * resolution *
                                                               config.unseen_gaps.max_grade);
    bool blocked = false;
    std::optional<float> ground;
    for (const SurfaceGrid::Surface& s : surfaces.surfaces(c)) {
      if (!known) {  // no level: only what no robot drives stops it
        blocked = blocked || !s.traversable;
        continue;
      }
      if (s.bottom >= h + reach)
        continue;
      if (!s.traversable || std::abs(s.top - h) > band)
        blocked = true;
      else if (!ground || std::abs(s.top - h) < std::abs(*ground - h))
        ground = s.top;
    }
    if (blocked) {
      grid.cells[c] = Occupancy::occupied;
    } else if (ground) {
      grid.cells[c] = Occupancy::free;
      grid.surface_height[c] = *ground;
    }
  }
}

}  // namespace

DrivableMap compute_drivable_map(const MlsMap& map, const SurfaceGrid& measured,
                                 const TraversabilityConfig& config, const Eigen::Vector3d& robot_ground) {
  const SurfaceGrid surfaces = fill_unseen_gaps(measured, map.resolution(), config);
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
  result.connected.assign(cells, 0);
  if (cells == 0)
    return result;

  // The robot's patch: the horizontal patch nearest its ground height in its cell or, since many scanners
  // do not see the ground under the robot, in the nearest ring of cells around it that has one. Any
  // horizontal patch: the robot stands there whatever the classification says.
  const auto [robot_col, robot_row] = surfaces.local(map.cell_of(robot_ground.x(), robot_ground.y()));
  const std::optional<std::uint32_t> start =
      surfaces.nearest_surface(robot_col, robot_row, robot_ground.z(), config.start_tolerance,
                               static_cast<int>(std::ceil(config.start_search_radius / map.resolution())),
                               SurfaceGrid::Standing::kHorizontal);
  if (!start) {
    classify_unreached(surfaces, config, map.resolution(), grid);  // obstacles only: no level is known
    return result;
  }
  result.start_found = true;
  const std::uint32_t start_surface = *start;
  const std::size_t start_cell = surfaces.cell_of_surface(start_surface);
  const int start_col = static_cast<int>(start_cell % static_cast<std::size_t>(region.width));
  const int start_row = static_cast<int>(start_cell / static_cast<std::size_t>(region.width));

  struct Item {
    int col;
    int row;
    float top;
    float variance;
  };
  std::vector<std::uint8_t> reached(surfaces.surface_count(), 0);
  std::vector<Item> stack;
  const auto reach = [&](int col, int row, std::uint32_t surface) {
    const SurfaceGrid::Surface& s = surfaces.surface(surface);
    reached[surface] = 1;
    const std::size_t c = surfaces.cell(col, row);
    if (result.connected[c] == 0)
      ++result.connected_cells;
    result.connected[c] = 1;
    grid.cells[c] = Occupancy::free;
    grid.surface_height[c] = s.top;
    stack.push_back({col, row, s.top, s.variance});
  };
  // The robot stands on its patch even if the classification (say, a slope estimate at a map edge) would
  // not enter it.
  reach(start_col, start_row, start_surface);

  constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    for (const auto& offset : kNeighbours) {
      const int col = item.col + offset[0];
      const int row = item.row + offset[1];
      const std::optional<std::uint32_t> next = surfaces.step_onto(col, row, item.top, item.variance);
      if (next && reached[*next] == 0)
        reach(col, row, *next);
    }
  }
  classify_unreached(surfaces, config, map.resolution(), grid);
  result.free_cells = static_cast<std::size_t>(std::ranges::count(grid.cells, Occupancy::free));
  return result;
}

CellRegion changed_region(const MlsMap& map, std::uint64_t version, const Eigen::Vector3d& robot_ground) {
  const CellIndex robot = map.cell_of(robot_ground.x(), robot_ground.y());
  return CellRegion::bounding(CellRegion::of_tiles(map.tiles_changed_since(version)),
                              CellRegion::of_tiles({MlsMap::tile_of(robot)}));
}

}  // namespace strata

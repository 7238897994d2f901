// strata_patch_planner_bench: planning across levels on the MLS patch graph of the campus world, against
// the occupancy-grid planner on the drivable map at the robot's level. Not a test: it prints one
// machine-readable line per measurement, "key=value" separated by spaces, first word the kind.
//
//   strata_patch_planner_bench [--resolution METRES] [--repeats N]
//
//   map      the surveyed campus (tests/support/world_survey.hpp): cells, patches, ms to build
//   prepare  ms to flatten the map (SurfaceGrid, on the mapping thread), to build the patch graph, and to
//            compute the drivable map and the occupancy planner (inflation, regions)
//   query    per goal: ms per query (median of --repeats) of the patch-graph A* and, for goals on the
//            robot's level, the occupancy planner's jump point search; path lengths
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/mls/drivable_map.hpp"
#include "core/navigation/patch_graph_planner.hpp"
#include "core/planning/grid_planner.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "tests/support/world_survey.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

struct Goal {
  const char* name;
  double x;
  double y;
  std::optional<double> z;
  bool same_level;  // reachable on the robot's level: the occupancy planner can answer it too
};

strata::OccupancyGrid occupancy_of(const strata::LevelGrid& level) {
  strata::OccupancyGrid grid(level.width, level.height, level.resolution, level.origin,
                             strata::CellState::unknown);
  for (std::size_t i = 0; i < level.cells.size(); ++i)
    grid.cells[i] = level.cells[i] == strata::Occupancy::free       ? strata::CellState::free
                    : level.cells[i] == strata::Occupancy::occupied ? strata::CellState::occupied
                                                                    : strata::CellState::unknown;
  return grid;
}

}  // namespace

int main(int argc, char** argv) {
  double resolution = 0.2;
  int repeats = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--resolution") == 0)
      resolution = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--repeats") == 0)
      repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  const strata::sim::World world(strata::sim::builtin_world("campus"));
  const Eigen::Vector3d robot(4.0, 9.5, 0.45);  // the lab, where the campus robot starts

  auto start = Clock::now();
  const strata::MlsMap map = strata::test::survey_world(world, -1, -40, 93, 13, resolution);
  std::printf("map world=campus resolution=%.2f cells=%zu patches=%zu build_ms=%.1f\n", resolution,
              map.occupied_cell_count(), map.patch_count(), ms_since(start));

  const strata::CellRegion region = strata::CellRegion::of_tiles(map.tile_indices());
  const strata::PatchGraphConfig config{.clearance_weight = 2.0};
  start = Clock::now();
  auto surfaces = std::make_shared<const strata::SurfaceGrid>(map, region, config.traversability);
  const double surfaces_ms = ms_since(start);
  start = Clock::now();
  const strata::PatchGraph graph(surfaces, map.resolution(), config);
  const double graph_ms = ms_since(start);
  start = Clock::now();
  const strata::DrivableMap drivable =
      strata::compute_drivable_map(map, config.traversability, robot, region);
  const double drivable_ms = ms_since(start);
  start = Clock::now();
  strata::GridPlanner occupancy(occupancy_of(drivable.grid), {.robot_radius = config.robot_radius});
  const double occupancy_ms = ms_since(start);
  std::printf(
      "prepare nodes=%zu surfaces_ms=%.1f patch_graph_ms=%.1f drivable_map_ms=%.1f "
      "occupancy_planner_ms=%.1f\n",
      graph.node_count(), surfaces_ms, graph_ms, drivable_ms, occupancy_ms);

  const std::vector<Goal> goals = {
      {"hallway", 40.0, 5.25, std::nullopt, true},
      {"campus_lawn", 60.0, -10.0, 0.0, false},
      {"bridge_deck", 84.0, -28.75, 3.0, false},
      {"under_bridge", 84.0, -36.0, 0.0, false},
      {"stairs_unreachable", 50.05, 7.5, std::nullopt, false},
      {"table_top_blocked", 4.0, 10.8, 1.21, false},
      {"wall_unreachable", 44.0, 3.9, std::nullopt, true},
  };
  for (const Goal& goal : goals) {
    std::vector<double> patch_ms;
    strata::PatchPath path;
    for (int r = 0; r < repeats; ++r) {
      start = Clock::now();
      path = strata::plan_on_patches(graph, robot, {.x = goal.x, .y = goal.y, .z = goal.z});
      patch_ms.push_back(ms_since(start));
    }
    std::printf("query goal=%s patch_status=\"%s\" patch_ms=%.2f patch_length=%.1f patch_expanded=%zu",
                goal.name, std::string(strata::describe(path.status)).c_str(), median(patch_ms), path.length,
                path.expanded);
    if (goal.same_level) {
      std::vector<double> grid_ms;
      strata::GridPath grid_path;
      const strata::OccupancyGrid level = occupancy_of(drivable.grid);
      const strata::GridCell from = level.cell_of(robot.head<2>());
      const strata::GridCell to = level.cell_of({goal.x, goal.y});
      for (int r = 0; r < repeats; ++r) {
        start = Clock::now();
        grid_path = occupancy.plan(from, to);
        grid_ms.push_back(ms_since(start));
      }
      std::printf(" grid_status=\"%s\" grid_ms=%.2f grid_length=%.1f",
                  std::string(strata::describe(grid_path.status)).c_str(), median(grid_ms),
                  grid_path.length * level.resolution);
    }
    std::printf("\n");
  }
  return 0;
}

// strata_planner_bench: measures the grid planner against the targets. Not a test: it prints one
// machine-readable line per measurement, "key=value" separated by spaces, first word the kind.
//
//   strata_planner_bench [--data DIR] [--radius METRES] [--repeats N] [--queries N (MovingAI: the first N)]
//
//   movingai  every query of pathfindingjs/64room_000 (512 x 512): median/p90/max ms per query (A*), and
//             the wavefront (whole-map Dijkstra + descent) on every 20th query; lengths checked against the
//             published optima. Target: median <= 5 ms.
//   nav2      Nav2's 2000 x 2000 benchmark map (0.05 m), corner to corner with the given robot radius:
//             ms per query (median of --repeats), expanded cells, path length. Target: <= 200 ms.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "bench/percentile.hpp"
#include "core/planning/grid_planner.hpp"
#include "drivers/io/map_server_reader.hpp"
#include "drivers/io/movingai_reader.hpp"

using strata::bench::percentile;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using strata::GridCell;
using strata::GridPath;
using strata::GridPlanner;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// CPU time of this thread: on a machine shared with other jobs it shows what a query costs when it has a
/// core to itself, next to the wall time it took here.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void bench_movingai(const fs::path& data, std::size_t max_queries) {
  const fs::path dir = data / "movingai/pathfindingjs";
  if (!fs::exists(dir / "64room_000.map")) {
    std::printf("movingai skipped=1 reason=\"no %s\"\n", (dir / "64room_000.map").c_str());
    return;
  }
  const strata::OccupancyGrid grid = strata::io::read_movingai_map(dir / "64room_000.map");
  const strata::io::MovingAiScenario scenario =
      strata::io::read_movingai_scenario(dir / "64room_000.map.scen");
  GridPlanner planner(grid);
  struct Timings {
    std::vector<double> wall_ms;
    std::vector<double> cpu_ms;
    double expanded = 0.0;
    int mismatches = 0;
  };
  Timings timings[2];  // jump point search, A*
  std::vector<double> wavefront_ms;
  int wavefront_mismatches = 0;
  for (std::size_t i = 0; i < std::min(scenario.queries.size(), max_queries); ++i) {
    const strata::io::MovingAiQuery& query = scenario.queries[i];
    for (const strata::SearchMethod method :
         {strata::SearchMethod::jump_point, strata::SearchMethod::astar}) {
      Timings& t = timings[method == strata::SearchMethod::jump_point ? 0 : 1];
      const double cpu_begin = thread_cpu_seconds();
      const GridPath path = planner.plan(query.start, query.goal, method);
      t.cpu_ms.push_back(1e3 * (thread_cpu_seconds() - cpu_begin));
      t.wall_ms.push_back(1e3 * path.seconds);
      t.expanded += static_cast<double>(path.expanded);
      if (!path.found() || std::abs(path.length - query.optimal_length) > 1e-3)
        ++t.mismatches;
    }
    if (i % 20 == 0) {
      const Clock::time_point begin = Clock::now();
      const GridPath followed = planner.follow(planner.wavefront(query.goal), query.start);
      wavefront_ms.push_back(1e3 * seconds_since(begin));
      if (!followed.found() || std::abs(followed.length - query.optimal_length) > 1e-3)
        ++wavefront_mismatches;
    }
  }
  for (int m = 0; m < 2; ++m) {
    const Timings& t = timings[m];
    std::printf(
        "movingai map=64room_000 size=%dx%d queries=%zu method=%s median_ms=%.3f p90_ms=%.3f max_ms=%.3f "
        "median_cpu_ms=%.3f mean_expanded=%.0f preparation_ms=%.2f mismatches=%d target_median_ms=5\n",
        grid.width, grid.height, t.wall_ms.size(), m == 0 ? "jps" : "astar", percentile(t.wall_ms, 0.5),
        percentile(t.wall_ms, 0.9), percentile(t.wall_ms, 1.0), percentile(t.cpu_ms, 0.5),
        t.expanded / static_cast<double>(t.wall_ms.size()), 1e3 * planner.preparation_seconds(),
        t.mismatches);
  }
  std::printf(
      "movingai map=64room_000 queries=%zu method=wavefront median_ms=%.3f p90_ms=%.3f max_ms=%.3f "
      "mismatches=%d\n",
      wavefront_ms.size(), percentile(wavefront_ms, 0.5), percentile(wavefront_ms, 0.9),
      percentile(wavefront_ms, 1.0), wavefront_mismatches);
}

/// The passable cell nearest to `corner` (by rings of growing Chebyshev radius) in the grid's largest
/// region, so the query is corner to corner even when the corner itself is inflated shut.
GridCell nearest_passable(const GridPlanner& planner, GridCell corner, int region) {
  const strata::TraversableGrid& grid = planner.traversable();
  for (int r = 0; r < std::max(grid.width(), grid.height()); ++r)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const GridCell c{corner.x + dx, corner.y + dy};
        if ((std::abs(dx) == r || std::abs(dy) == r) && planner.regions().region(grid, c) == region)
          return c;
      }
  return corner;
}

int largest_region(const GridPlanner& planner) {
  std::vector<int> sizes(static_cast<std::size_t>(planner.regions().count()));
  const strata::TraversableGrid& grid = planner.traversable();
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x)
      if (const int r = planner.regions().region(grid, {x, y}); r >= 0)
        ++sizes[static_cast<std::size_t>(r)];
  return static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
}

void bench_nav2(const fs::path& data, double radius, int repeats) {
  const fs::path yaml = data / "nav2/100by100_20.yaml";
  if (!fs::exists(yaml)) {
    std::printf("nav2 skipped=1 reason=\"no %s\"\n", yaml.c_str());
    return;
  }
  Clock::time_point begin = Clock::now();
  const strata::OccupancyGrid grid = strata::io::read_map_server_map(yaml);
  const double load_ms = 1e3 * seconds_since(begin);
  GridPlanner planner(grid, {radius, true});
  const int region = largest_region(planner);
  const GridCell start = nearest_passable(planner, {0, 0}, region);
  const GridCell goal = nearest_passable(planner, {grid.width - 1, grid.height - 1}, region);
  const auto start_m = grid.center_of(start);
  const auto goal_m = grid.center_of(goal);
  std::printf(
      "nav2 map=100by100_20 size=%dx%d resolution=%.3f robot_radius_m=%.3f start_m=%.3f,%.3f "
      "goal_m=%.3f,%.3f "
      "straight_line_m=%.3f\n",
      grid.width, grid.height, grid.resolution, radius, start_m.x(), start_m.y(), goal_m.x(), goal_m.y(),
      (goal_m - start_m).norm());
  for (const strata::SearchMethod method : {strata::SearchMethod::jump_point, strata::SearchMethod::astar}) {
    std::vector<double> wall_ms;
    std::vector<double> cpu_ms;
    GridPath path;
    for (int i = 0; i < repeats; ++i) {
      const double cpu_begin = thread_cpu_seconds();
      path = planner.plan(start, goal, method);
      cpu_ms.push_back(1e3 * (thread_cpu_seconds() - cpu_begin));
      wall_ms.push_back(1e3 * path.seconds);
    }
    std::printf(
        "nav2 map=100by100_20 method=%s found=%d length_m=%.3f median_ms=%.2f median_cpu_ms=%.2f "
        "expanded=%zu "
        "repeats=%d target_ms=200\n",
        method == strata::SearchMethod::jump_point ? "jps" : "astar", path.found() ? 1 : 0,
        path.length * grid.resolution, percentile(wall_ms, 0.5), percentile(cpu_ms, 0.5), path.expanded,
        repeats);
  }
  std::vector<double> wavefront_ms;
  GridPath followed;
  for (int i = 0; i < std::min(repeats, 3); ++i) {
    begin = Clock::now();
    followed = planner.follow(planner.wavefront(goal), start);
    wavefront_ms.push_back(1e3 * seconds_since(begin));
  }
  std::printf("nav2 map=100by100_20 method=wavefront found=%d length_m=%.3f median_ms=%.2f expanded=%zu\n",
              followed.found() ? 1 : 0, followed.length * grid.resolution, percentile(wavefront_ms, 0.5),
              followed.expanded);
  std::printf("nav2 map=100by100_20 load_ms=%.1f preparation_ms=%.1f regions=%d\n", load_ms,
              1e3 * planner.preparation_seconds(), planner.regions().count());
}

}  // namespace

int main(int argc, char** argv) {
  fs::path data = STRATA_DATA_DIR;
  if (const char* from_env = std::getenv("STRATA_DATA_DIR"))
    data = from_env;
  double radius = 0.22;  // Nav2's default robot_radius (a TurtleBot-sized base)
  int repeats = 5;
  std::size_t queries = std::numeric_limits<std::size_t>::max();  // the scenario's every query
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (arg == "--radius" && i + 1 < argc)
      radius = std::atof(argv[++i]);
    else if (arg == "--repeats" && i + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--queries" && i + 1 < argc)
      queries = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
    else {
      std::fprintf(stderr, "usage: %s [--data DIR] [--radius METRES] [--repeats N] [--queries N]\n", argv[0]);
      return 2;
    }
  }
  bench_movingai(data, queries);
  bench_nav2(data, radius, repeats);
  return 0;
}

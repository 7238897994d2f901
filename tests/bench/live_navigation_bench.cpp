// strata_live_navigation_bench: how much of what the robot has seen can it be sent to? The simulated
// robot drives its world's demo route for a while and its scans are mapped at their true poses, as the
// live server maps them (0.1 m MLS). Then every place that a survey of the world says the robot can
// reach with room to spare, and that the live map has measured at that height, is tried as a goal from
// where the robot stands (tests/support/seen_goals.hpp). Not a test: it prints one line per
// measurement, "key=value" separated by spaces.
//
//   strata_live_navigation_bench [--world yard|campus] [--scanner tilting|lidar] [--seconds S]
//                                [--spacing M] [--max-gap M] [--track 0|1] [--ascii FILE]
//                                [--map FILE --at X,Y,Z] [--save-map FILE] [--goals-at X,Y,Z;X,Y,Z...]
//                                [--passed X,Y,Z;...] [--inspect X,Y,HALF]
//
//   --max-gap: the longest unseen gap inferred as ground (0: none)
//   --track: 1 (default) marks the ground the robot drove over, as the live map does; 0 does not
//   --map, --at: a map saved by the server, and where the robot stands on it, instead of a simulated drive
//   --save-map: writes the map the goals are tried on (a native map file)
//   --goals-at: also plans to these places, one line each ("place"), e.g. the campus ramp's goals on a map
//           strata_goal_drive_bench --dump saved (issue 58)
//   --passed X,Y,Z;...: places the robot passed, marked on the loaded map first (MlsMap::mark_passed), as
//           the mapping marks the scans it dropped
//   --inspect prints each cell's surfaces: bottom..top, sd, flags (V vertical, T traversable, I inferred,
//           D driven, K the robot's track, P passable: room for the robot) and c= the clearance
//   map     scans mapped, cells and patches of the live map, graph nodes, ms to build the graph
//   goals   per distance band from the robot: goals tried, planned (a way found; strata_goal_drive_bench
//           drives them), and why the others failed;
//           then 2-20 m (issue 21's band), then all bands, with the median and longest planning time
//   --ascii writes the live patch graph as text, north up: '.' room for the robot (':' on ground inferred
//           across an unseen gap), ',' drivable without room, '#' not drivable, ' ' unseen,
//           'o' goal planned, 'x' goal failed, 'R' the robot
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/mls/mls_file.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "tests/support/seen_goals.hpp"

namespace {

using namespace strata;

struct Options {
  std::string world = "yard";
  std::string scanner = "tilting";
  double seconds = 30.0;
  double spacing = 0.5;
  double max_gap = UnseenGapConfig{}.max_gap;
  bool track = true;
  std::string ascii;
  std::string map;                        ///< a saved map instead of a simulated drive (with `at`)
  Eigen::Vector3d at{0, 0, 0};            ///< where the robot stands on that map
  std::string save_map;                   ///< where to write the map; empty: not written
  std::vector<Eigen::Vector3d> goals_at;  ///< places planned to besides the seen goals
  double step_sigmas = TraversabilityConfig{}.step_sigmas;
  double max_uncertain_step = TraversabilityConfig{}.max_uncertain_step;
  std::vector<Eigen::Vector3d> inspect;  ///< cells whose surfaces are printed (x, y, half width in cells)
  std::vector<Eigen::Vector3d> passed;   ///< places the robot passed, marked on the loaded map in order
};

/// "X,Y,Z;X,Y,Z;..." as points; exits on a malformed list.
std::vector<Eigen::Vector3d> places(const char* flag, const char* value) {
  std::vector<Eigen::Vector3d> out;
  for (const char* item = value; *item != '\0';) {
    Eigen::Vector3d place;
    int used = 0;
    if (std::sscanf(item, "%lf,%lf,%lf%n", &place.x(), &place.y(), &place.z(), &used) != 3) {
      std::fprintf(stderr, "%s: \"%s\" is not X,Y,Z;...\n", flag, value);
      std::exit(2);
    }
    out.push_back(place);
    item += used;
    item += *item == ';' ? 1 : 0;
  }
  return out;
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--world")
      options.world = value;
    else if (key == "--scanner")
      options.scanner = value;
    else if (key == "--seconds")
      options.seconds = std::atof(value);
    else if (key == "--spacing")
      options.spacing = std::atof(value);
    else if (key == "--max-gap")
      options.max_gap = std::atof(value);
    else if (key == "--track")
      options.track = std::atoi(value) != 0;
    else if (key == "--ascii")
      options.ascii = value;
    else if (key == "--map")
      options.map = value;
    else if (key == "--save-map")
      options.save_map = value;
    else if (key == "--at")
      std::sscanf(value, "%lf,%lf,%lf", &options.at.x(), &options.at.y(), &options.at.z());
    else if (key == "--step-sigmas")
      options.step_sigmas = std::atof(value);
    else if (key == "--max-uncertain-step")
      options.max_uncertain_step = std::atof(value);
    else if (key == "--inspect") {
      Eigen::Vector3d at;
      std::sscanf(value, "%lf,%lf,%lf", &at.x(), &at.y(), &at.z());
      options.inspect.push_back(at);
    } else if (key == "--goals-at")
      options.goals_at = places("--goals-at", value);
    else if (key == "--passed")
      options.passed = places("--passed", value);
  }
  return options;
}

struct Band {
  int tried = 0;
  int planned = 0;
  std::map<std::string, int> failed;
};

void write_ascii(const std::string& file, const PatchGraph& graph, const Eigen::Vector3d& robot,
                 const std::vector<test::SeenGoal>& goals) {
  const CellRegion& region = graph.surfaces().region();
  std::vector<std::string> rows(static_cast<std::size_t>(region.height),
                                std::string(static_cast<std::size_t>(region.width), ' '));
  for (PatchGraph::Node node = 0; node < graph.node_count(); ++node) {
    const auto [col, row] = graph.cell(node);
    char& c = rows[static_cast<std::size_t>(row)][static_cast<std::size_t>(col)];
    const double dz = std::abs(graph.position(node).z() - robot.z());
    const char mark = graph.passable(node)      ? (graph.inferred(node) ? ':' : '.')
                      : graph.traversable(node) ? ','
                                                : '#';
    if (c == ' ' || dz < 0.5)  // the robot's level wins
      c = mark;
  }
  const auto put = [&](const Eigen::Vector3d& p, char mark) {
    const int col = static_cast<int>(std::floor(p.x() / graph.resolution())) - region.min.x;
    const int row = static_cast<int>(std::floor(p.y() / graph.resolution())) - region.min.y;
    if (col >= 0 && row >= 0 && col < region.width && row < region.height)
      rows[static_cast<std::size_t>(row)][static_cast<std::size_t>(col)] = mark;
  };
  for (const test::SeenGoal& goal : goals)
    put(goal.position, goal.path.found() ? 'o' : 'x');
  put(robot, 'R');
  std::ofstream out(file);
  for (auto row = rows.rbegin(); row != rows.rend(); ++row)
    out << *row << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  auto world = std::make_shared<const sim::World>(sim::builtin_world(options.world));
  sim::SimulatorConfig config;
  config.scanner = options.scanner == "lidar" ? sim::ScannerKind::kLidar : sim::ScannerKind::kTilting;
  sim::Simulator simulator(world, config);
  MlsMap live{MlsConfig{}};
  int scans = 0;
  if (!options.map.empty())
    live = load_mls_map(options.map);
  for (const Eigen::Vector3d& ground : options.passed)  // as the mapping marks a dropped scan's place
    live.mark_passed(ground);
  for (double t = 0.0; options.map.empty() && t < options.seconds; t += 0.1) {
    simulator.step(0.1);
    for (const ScanEvent& scan : simulator.take_scans()) {
      test::map_at_truth(live, scan, 0.3, options.track);
      ++scans;
    }
  }
  if (!options.save_map.empty())
    save_mls_map(live, options.save_map);
  const Eigen::Vector3d robot = options.map.empty() ? simulator.sample().truth->position : options.at;

  PatchGraphConfig graph_config{.clearance_weight = 2.0};  // the navigator's
  graph_config.traversability.unseen_gaps.max_gap = options.max_gap;
  graph_config.traversability.step_sigmas = options.step_sigmas;
  graph_config.traversability.max_uncertain_step = options.max_uncertain_step;
  const auto build_start = std::chrono::steady_clock::now();
  const PatchGraph seen(std::make_shared<const SurfaceGrid>(live, CellRegion::of_tiles(live.tile_indices()),
                                                            graph_config.traversability),
                        live.resolution(), graph_config);
  const double build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - build_start).count();
  std::printf(
      "map world=%s scanner=%s seconds=%.0f scans=%d cells=%zu patches=%zu nodes=%zu graph_ms=%.1f "
      "robot=%.2f,%.2f,%.2f\n",
      options.world.c_str(), options.scanner.c_str(), options.seconds, scans, live.occupied_cell_count(),
      live.patch_count(), seen.node_count(), build_ms, robot.x(), robot.y(), robot.z());

  for (const Eigen::Vector3d& at : options.inspect) {
    const SurfaceGrid& grid = seen.surfaces();
    const auto [centre_col, centre_row] = grid.local(live.cell_of(at.x(), at.y()));
    const int half = static_cast<int>(at.z());
    for (int row = centre_row + half; row >= centre_row - half; --row)
      for (int col = centre_col - half; col <= centre_col + half; ++col) {
        if (!grid.contains_local(col, row))
          continue;
        std::printf("cell %d,%d", col - centre_col, row - centre_row);
        const auto cell_surfaces = grid.surfaces(grid.cell(col, row));
        for (std::size_t i = 0; i < cell_surfaces.size(); ++i) {
          const SurfaceGrid::Surface& s = cell_surfaces[i];
          const auto node = static_cast<PatchGraph::Node>(grid.first_surface(grid.cell(col, row)) + i);
          std::printf(" [%.3f..%.3f sd=%.3f%s%s%s%s%s%s c=%.2f]", static_cast<double>(s.bottom),
                      static_cast<double>(s.top), std::sqrt(static_cast<double>(s.variance)),
                      s.vertical ? " V" : "", s.traversable ? " T" : "", s.inferred ? " I" : "",
                      s.driven ? " D" : "", s.track ? " K" : "", seen.passable(node) ? " P" : "",
                      static_cast<double>(seen.clearance(node)));
        }
        std::printf("\n");
      }
  }
  for (const Eigen::Vector3d& place : options.goals_at) {
    // As the navigator moves a goal too near an edge: 0.1 of its distance, 0.5-2 m.
    const double room = std::clamp(0.1 * std::hypot(place.x() - robot.x(), place.y() - robot.y()), 0.5, 2.0);
    const PatchPath path = plan_on_patches(
        seen, robot, {.x = place.x(), .y = place.y(), .z = place.z(), .room_search_radius = room});
    std::printf("place at=%.2f,%.2f,%.2f status='%s' length_m=%.1f\n", place.x(), place.y(), place.z(),
                std::string(describe(path.status)).c_str(), path.length);
  }
  const std::vector<test::SeenGoal> goals = test::plan_to_seen_goals(*world, seen, robot, options.spacing);
  constexpr std::array<double, 6> kBands{2.0, 5.0, 10.0, 15.0, 20.0, 1e9};
  std::array<Band, kBands.size()> bands;
  std::vector<double> plan_ms;
  for (const test::SeenGoal& goal : goals) {
    const auto b = static_cast<std::size_t>(std::lower_bound(kBands.begin(), kBands.end(), goal.distance) -
                                            kBands.begin());
    ++bands[b].tried;
    if (goal.path.found())
      ++bands[b].planned;
    else
      ++bands[b].failed[std::string(describe(goal.path.status))];
    plan_ms.push_back(goal.plan_ms);
  }
  int all_tried = 0;
  int all_planned = 0;
  int near_tried = 0;  // 2-20 m: issue 21's target
  int near_planned = 0;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    std::string failed;
    for (const auto& [reason, count] : bands[b].failed)
      failed += " '" + reason + "'=" + std::to_string(count);
    std::printf("goals within_m=%.0f tried=%d planned=%d share=%.2f%s\n", std::min(kBands[b], 999.0),
                bands[b].tried, bands[b].planned,
                bands[b].tried > 0 ? static_cast<double>(bands[b].planned) / bands[b].tried : 0.0,
                failed.c_str());
    all_tried += bands[b].tried;
    all_planned += bands[b].planned;
    if (b >= 1 && b <= 4) {
      near_tried += bands[b].tried;
      near_planned += bands[b].planned;
    }
  }
  std::printf("goals from_m=2 within_m=20 tried=%d planned=%d share=%.2f\n", near_tried, near_planned,
              near_tried > 0 ? static_cast<double>(near_planned) / near_tried : 0.0);
  std::sort(plan_ms.begin(), plan_ms.end());
  std::printf("goals all tried=%d planned=%d share=%.2f plan_ms_median=%.2f plan_ms_max=%.2f\n", all_tried,
              all_planned, all_tried > 0 ? static_cast<double>(all_planned) / all_tried : 0.0,
              plan_ms.empty() ? 0.0 : plan_ms[plan_ms.size() / 2], plan_ms.empty() ? 0.0 : plan_ms.back());
  if (!options.ascii.empty())
    write_ascii(options.ascii, seen, robot, goals);
  return 0;
}

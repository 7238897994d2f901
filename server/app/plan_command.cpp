#include "server/app/plan_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "core/planning/cost_field.hpp"
#include "core/planning/grid_planner.hpp"
#include "drivers/io/map_server_reader.hpp"
#include "drivers/io/movingai_reader.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::app {
namespace {

using Clock = std::chrono::steady_clock;

/// A map as the command uses it: a MovingAI map speaks in cells (resolution 1, row 0 at the top, as in its
/// scenario files), a map_server map in metres.
struct LoadedMap {
  OccupancyGrid grid;
  bool metric = true;
};

LoadedMap load_map(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  if (extension == ".yaml" || extension == ".yml")
    return {io::read_map_server_map(path), true};
  if (extension == ".map")
    return {io::read_movingai_map(path), false};
  throw std::invalid_argument(path.string() +
                              ": unknown map format (expected a map_server .yaml or a MovingAI .map)");
}

Eigen::Vector2d parse_point(const std::string& option, const std::string& text) {
  const std::vector<std::string_view> fields = io::split_fields(text);
  if (fields.size() == 2 && text.find(',') != std::string::npos) {
    const std::optional<double> x = io::parse_number(fields[0]);
    const std::optional<double> y = io::parse_number(fields[1]);
    if (x && y && std::isfinite(*x) && std::isfinite(*y))
      return {*x, *y};
  }
  throw std::invalid_argument(option + " needs two numbers \"x,y\", got \"" + text + "\"");
}

/// The cell a point names: the containing cell (a MovingAI map has resolution 1 and origin 0, so "x,y" there
/// is the cell itself).
GridCell cell_of(const LoadedMap& map, const Eigen::Vector2d& point) {
  return map.grid.cell_of(point);
}

/// Where a path cell is printed: its centre in metres, or the cell for a MovingAI map.
Eigen::Vector2d point_of(const LoadedMap& map, GridCell cell) {
  return map.metric ? map.grid.center_of(cell) : Eigen::Vector2d(cell.x, cell.y);
}

}  // namespace

CLI::App* add_plan_command(CLI::App& app, PlanOptions& options) {
  auto* command = app.add_subcommand(
      "plan",
      "Plan the shortest path on a 2D map: 8-connected, diagonal sqrt(2), no corner cutting, obstacles\n"
      "inflated by the robot radius. Prints the path length, expanded cells and time. On a map_server map\n"
      "(.yaml + .pgm) coordinates are metres in the map frame; on a MovingAI .map they are cells (column,\n"
      "row). Exit code 3 when there is no path (the reason is printed), 1 on bad input.");
  command->add_option("--map", options.map, "map_server .yaml or MovingAI .map")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--start", options.start, "Start \"x,y\"")->required();
  command->add_option("--goal", options.goal, "Goal \"x,y\"")->required();
  command->add_option("--robot-radius", options.robot_radius, "Robot radius (metres; cells on a .map)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  command
      ->add_option(
          "--method", options.method,
          "jps (jump point search: fastest; expanded counts jump points), astar (expands every cell\n"
          "it reaches) or wavefront (Dijkstra from the goal over the whole map); all exact")
      ->capture_default_str()
      ->check(CLI::IsMember({"jps", "astar", "wavefront"}));
  command->add_flag("--unknown-is-free", options.unknown_is_free, "Plan through unknown cells");
  command->add_flag("--json", options.json, "Print one JSON object instead of text");
  command->add_flag("--path", options.path, "Also print the path's points");
  return command;
}

int run_plan(const PlanOptions& options) {
  const Eigen::Vector2d start_point = parse_point("--start", options.start);
  const Eigen::Vector2d goal_point = parse_point("--goal", options.goal);
  const Clock::time_point load_begin = Clock::now();
  const LoadedMap map = load_map(options.map);
  const double load_seconds = std::chrono::duration<double>(Clock::now() - load_begin).count();

  const double resolution = map.metric ? map.grid.resolution : 1.0;
  GridPlanner planner(map.grid, {options.robot_radius, !options.unknown_is_free});
  const GridCell start = cell_of(map, start_point);
  const GridCell goal = cell_of(map, goal_point);
  GridPath path;
  if (options.method == "wavefront") {
    const Clock::time_point begin = Clock::now();
    const CostField field = planner.wavefront(goal);
    path = planner.follow(field, start);
    path.seconds = std::chrono::duration<double>(Clock::now() - begin).count();
  } else {
    path =
        planner.plan(start, goal, options.method == "astar" ? SearchMethod::astar : SearchMethod::jump_point);
  }
  const double length = path.length * resolution;
  const char* unit = map.metric ? "m" : "cells";

  if (options.json) {
    nlohmann::json out{
        {"found", path.found()},
        {"status", describe(path.status)},
        {"units", unit},
        {"length", path.found() ? nlohmann::json(length) : nlohmann::json(nullptr)},
        {"expanded", path.expanded},
        {"seconds", path.seconds},
        {"preparation_seconds", planner.preparation_seconds()},
        {"load_seconds", load_seconds},
        {"method", options.method},
        {"robot_radius", options.robot_radius},
        {"map", {{"width", map.grid.width}, {"height", map.grid.height}, {"resolution", resolution}}},
        {"start", {{"x", start_point.x()}, {"y", start_point.y()}, {"cell", {start.x, start.y}}}},
        {"goal", {{"x", goal_point.x()}, {"y", goal_point.y()}, {"cell", {goal.x, goal.y}}}},
    };
    if (options.path) {
      nlohmann::json points = nlohmann::json::array();
      for (const GridCell& cell : path.cells) {
        const Eigen::Vector2d p = point_of(map, cell);
        points.push_back({p.x(), p.y()});
      }
      out["path"] = points;
    }
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("map: %s (%d x %d cells, %g %s per cell)\n", options.map.c_str(), map.grid.width,
                map.grid.height, resolution, unit);
    if (path.found())
      std::printf("length: %.4f %s\n", length, unit);
    else
      std::printf("unreachable: %s\n", std::string(describe(path.status)).c_str());
    std::printf("expanded: %zu %s\ntime: %.2f ms (%s; map read %.1f ms, inflation and regions %.1f ms)\n",
                path.expanded, options.method == "jps" ? "jump points" : "cells", 1e3 * path.seconds,
                options.method.c_str(), 1e3 * load_seconds, 1e3 * planner.preparation_seconds());
    if (options.path) {
      std::printf("path (%zu points, %s):\n", path.cells.size(), map.metric ? "cell centres, m" : "cells");
      for (const GridCell& cell : path.cells) {
        const Eigen::Vector2d p = point_of(map, cell);
        std::printf("  %g %g\n", p.x(), p.y());
      }
    }
  }
  return path.found() ? 0 : kNoPathExitCode;
}

}  // namespace strata::app

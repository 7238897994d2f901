#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace strata::app {

struct PlanOptions {
  std::string map;    ///< map_server .yaml (metres) or MovingAI .map (cells)
  std::string start;  ///< "x,y"
  std::string goal;   ///< "x,y"
  double robot_radius = 0.0;
  std::string method = "jps";
  bool unknown_is_free = false;
  bool json = false;
  bool path = false;
};

/// Exit code of `strata plan` when the map was read but there is no path (start or goal outside the map or
/// blocked, or not connected). Bad options and unreadable files exit with 1 like every command.
inline constexpr int kNoPathExitCode = 3;

/// Adds `strata plan --map FILE --start x,y --goal x,y [--robot-radius R] [--json] [--path]` to `app`.
CLI::App* add_plan_command(CLI::App& app, PlanOptions& options);

/// Plans on the map and prints the path length, expanded cells and time (and the path with --path).
/// Returns 0 with a path, kNoPathExitCode without one.
int run_plan(const PlanOptions& options);

}  // namespace strata::app

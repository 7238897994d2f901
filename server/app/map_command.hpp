#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace strata::app {

struct MapBuildOptions {
  std::vector<std::string> scans;  ///< point cloud files (.pcd, .ply, .3d, .xyz, ...)
  std::vector<std::string> poses;  ///< one per scan: 3DTK .pose or .frames; none = scans already in map frame
  std::string output;
  double resolution = 0.1;
  double gap = 1.0;
};

struct MapExportOptions {
  std::string input;
  std::string ply;
  std::string pgm_yaml;  ///< the YAML path; the PGM goes next to it
  std::string mcap;      ///< ROS 2 messages: patches, the drivable map (with --robot), keyframes
  bool mcap_uncompressed = false;
  std::string robot;  ///< "x y z": the ground point the robot stands on, for the drivable map
  double max_step = 0.08;
  double max_slope_degrees = 15.0;
  double robot_height = 1.0;
};

struct MapCommand {
  CLI::App* build = nullptr;
  CLI::App* export_ = nullptr;
  CLI::App* map = nullptr;
};

/// Adds `strata map build --scans ... [--poses ...] -o FILE` and
/// `strata map export FILE [--ply OUT] [--pgm OUT.yaml --robot x,y,z] [--mcap OUT.mcap]`.
MapCommand add_map_command(CLI::App& app, MapBuildOptions& build, MapExportOptions& export_options);

/// Builds an MLS map from the scans at their poses and saves it; prints a JSON summary. Returns 0.
int run_map_build(const MapBuildOptions& options);
/// Loads a native map file and writes the requested exports; prints a JSON summary. Returns 0.
int run_map_export(const MapExportOptions& options);

}  // namespace strata::app

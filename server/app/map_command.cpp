#include "server/app/map_command.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/files/atomic_file.hpp"
#include "core/geometry/pose_text.hpp"
#include "core/mls/drivable_map.hpp"
#include "core/mls/map_export.hpp"
#include "core/mls/mls_file.hpp"
#include "core/mls/mls_map.hpp"
#include "drivers/io/point_cloud_file.hpp"
#include "drivers/io/threedtk_reader.hpp"
#include "drivers/ros2/map_messages.hpp"

namespace strata::app {
namespace {

/// --robot in the command line's one syntax (x,y,z), or the old "x y z" with a warning that says what to
/// write.
Eigen::Vector3d parse_robot_point(const std::string& text) {
  constexpr const char* kSyntax = "--pgm needs --robot x,y,z (the ground point the robot stands on, metres)";
  if (text.find(',') == std::string::npos) {
    Eigen::Vector3d robot;
    std::istringstream in(text);
    std::string extra;
    if (!(in >> robot.x() >> robot.y() >> robot.z()) || (in >> extra) || !robot.allFinite())
      throw std::runtime_error(kSyntax);
    spdlog::warn("--robot \"{}\" is the old form (spaces); write --robot {},{},{}", text, robot.x(),
                 robot.y(), robot.z());
    return robot;
  }
  try {
    return parse_point_text(text);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(std::string(kSyntax) + ": " + error.what());
  }
}

Eigen::Isometry3d read_pose(const std::filesystem::path& path) {
  if (path.extension() == ".pose")
    return io::read_3dtk_pose(path);
  if (path.extension() == ".frames")
    return io::read_3dtk_frames(path);
  throw std::runtime_error("unknown pose file type (want .pose or .frames): " + path.string());
}

}  // namespace

MapCommand add_map_command(CLI::App& app, MapBuildOptions& build, MapExportOptions& export_options) {
  MapCommand command;
  command.map = app.add_subcommand("map", "Build an MLS map offline from scans, or export one");
  command.map->require_subcommand(1);

  command.build = command.map->add_subcommand("build", "Build an MLS map from registered scans and save it");
  command.build->add_option("--scans", build.scans, "Scan files (.pcd, .ply, .3d, .xyz, .csv)")
      ->required()
      ->check(CLI::ExistingFile);
  command.build
      ->add_option(
          "--poses", build.poses,
          "One pose per scan, in order: 3DTK .pose or slam6D .frames (omit: scans are in the map frame)")
      ->check(CLI::ExistingFile);
  command.build->add_option("-o,--output", build.output, "Native map file to write")->required();
  command.build->add_option("--resolution", build.resolution, "Cell size, metres")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 10.0));
  command.build->add_option("--gap", build.gap, "Gap that separates two levels in a cell (gamma), metres")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 100.0));

  command.export_ =
      command.map->add_subcommand("export", "Export a native map file as PLY and/or ROS PGM+YAML");
  command.export_->add_option("input", export_options.input, "Native map file")
      ->required()
      ->check(CLI::ExistingFile);
  command.export_->add_option("--ply", export_options.ply, "Write the patches as a PLY point cloud");
  command.export_->add_option(
      "--pgm", export_options.pgm_yaml,
      "Write the drivable map at the robot's level: the map_server YAML (PGM beside it)");
  command.export_->add_option(
      "--mcap", export_options.mcap,
      "Write an MCAP file of ROS 2 messages: the patches, the keyframes' path and tf, and with --robot the "
      "drivable map (docs/interop.md)");
  command.export_->add_flag("--mcap-uncompressed", export_options.mcap_uncompressed,
                            "The MCAP file's chunks without zstd");
  command.export_->add_option(
      "--robot", export_options.robot,
      "x,y,z: the ground point the robot stands on, metres (needed with --pgm; with --mcap, adds /map)");
  command.export_->add_option("--max-step", export_options.max_step, "Highest step the robot climbs, metres")
      ->capture_default_str();
  command.export_->add_option("--max-slope", export_options.max_slope_degrees, "Steepest slope, degrees")
      ->capture_default_str();
  command.export_
      ->add_option("--robot-height", export_options.robot_height, "Clearance the robot needs, metres")
      ->capture_default_str();
  return command;
}

int run_map_build(const MapBuildOptions& options) {
  if (!options.poses.empty() && options.poses.size() != options.scans.size())
    throw std::runtime_error("give one pose per scan (" + std::to_string(options.scans.size()) + " scans, " +
                             std::to_string(options.poses.size()) + " poses)");
  MlsConfig config;
  config.resolution = options.resolution;
  config.gap = options.gap;
  MlsMap map(config);
  std::size_t points = 0;
  double insert_seconds = 0;
  for (std::size_t i = 0; i < options.scans.size(); ++i) {
    const Eigen::Isometry3d pose =
        options.poses.empty() ? Eigen::Isometry3d::Identity() : read_pose(options.poses[i]);
    const PointCloud cloud = transformed(io::read_point_cloud(options.scans[i]).points, pose);
    const auto start = std::chrono::steady_clock::now();
    map.insert_scan(cloud, pose.translation());
    insert_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    points += cloud.size();
  }
  save_mls_map(map, options.output);
  std::printf(
      "{\"output\":\"%s\",\"scans\":%zu,\"points\":%zu,\"insert_s\":%.3f,\"tiles\":%zu,\"occupied_cells\":%"
      "zu,"
      "\"patches\":%zu}\n",
      options.output.c_str(), options.scans.size(), points, insert_seconds, map.tile_count(),
      map.occupied_cell_count(), map.patch_count());
  return 0;
}

int run_map_export(const MapExportOptions& options) {
  if (options.ply.empty() && options.pgm_yaml.empty() && options.mcap.empty())
    throw std::runtime_error("nothing to export: give --ply, --pgm and/or --mcap");
  const MapFile file = load_map_file(options.input);
  const MlsMap& map = file.map;
  std::string summary =
      "{\"input\":\"" + options.input + "\",\"patches\":" + std::to_string(map.patch_count());
  if (!options.ply.empty()) {
    write_mls_ply(map, options.ply);
    summary += ",\"ply\":\"" + options.ply + "\"";
  }
  // The drivable map at the robot's level: --pgm needs it, --mcap adds it when --robot says where.
  std::optional<DrivableMap> drivable;
  if (!options.pgm_yaml.empty() || (!options.mcap.empty() && !options.robot.empty())) {
    const Eigen::Vector3d robot = parse_robot_point(options.robot);
    TraversabilityConfig config;
    config.max_step = options.max_step;
    config.max_slope = options.max_slope_degrees * std::numbers::pi / 180.0;
    config.robot_height = options.robot_height;
    drivable = compute_drivable_map(map, config, robot, CellRegion::of_tiles(map.tile_indices()));
    if (!drivable->start_found)
      throw std::runtime_error("no ground patch near the robot position " + options.robot);
  }
  if (!options.mcap.empty()) {
    const std::vector<Eigen::Isometry3d> trajectory =
        file.localization ? file.localization->keyframe_poses : std::vector<Eigen::Isometry3d>();
    const std::string bytes =
        ros2::map_as_mcap({.map = &map,
                           .drivable = drivable ? &drivable->grid : nullptr,
                           .trajectory = trajectory,
                           .stamp_ns = ros2::system_time_ns()},
                          options.mcap_uncompressed ? mcap::Compression::kNone : mcap::Compression::kZstd);
    write_file_atomically(options.mcap, bytes, Durability::kOrdered);
    summary += ",\"mcap\":\"" + options.mcap + "\",\"mcap_bytes\":" + std::to_string(bytes.size()) +
               ",\"keyframes\":" + std::to_string(trajectory.size());
  }
  if (!options.pgm_yaml.empty()) {
    const std::filesystem::path pgm = write_ros_map(drivable->grid, options.pgm_yaml);
    summary += ",\"yaml\":\"" + options.pgm_yaml + "\",\"pgm\":\"" + pgm.string() +
               "\",\"free_cells\":" + std::to_string(drivable->free_cells) +
               ",\"connected_cells\":" + std::to_string(drivable->connected_cells) +
               ",\"width\":" + std::to_string(drivable->grid.width) +
               ",\"height\":" + std::to_string(drivable->grid.height);
  }
  std::printf("%s}\n", summary.c_str());
  return 0;
}

}  // namespace strata::app

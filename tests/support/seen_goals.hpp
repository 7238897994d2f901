#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/navigation/patch_graph_planner.hpp"
#include "drivers/scan_event.hpp"
#include "drivers/sim/world/world.hpp"
#include "tests/support/world_survey.hpp"

namespace strata::test {

/// Maps a simulated scan at its true pose, as the mapping worker maps a registered one.
/// With `mark_ground`, the ground under the robot is marked driven, as the live map does.
inline void map_at_truth(MlsMap& map, const ScanEvent& scan, double min_range = 0.3,
                         bool mark_ground = true) {
  const Eigen::Isometry3d map_from_sensor = scan.truth->to_isometry() * scan.sensor_to_base;
  PointCloud points;
  for (const Eigen::Vector3f& p : scan.points) {
    const double range = p.cast<double>().norm();
    if (range > min_range && (scan.max_range <= 0.0 || range < scan.max_range - 1e-3))
      points.push_back(map_from_sensor * p.cast<double>());
  }
  map.insert_scan(points, map_from_sensor.translation(),
                  mark_ground ? std::optional<Eigen::Vector3d>(scan.truth->position) : std::nullopt);
}

/// One goal an operator could pick on the live map, and what the planner made of it.
struct SeenGoal {
  Eigen::Vector3d position;
  double distance = 0.0;  ///< from the robot, in the plane
  PatchPath path;
  double plan_ms = 0.0;
};

/// The world as the robot's planner would see it had it scanned every surface: what the seen goals are
/// judged against. Built with the planner's configuration and map resolution.
inline PatchGraph surveyed_graph(const sim::World& world, double resolution, const PatchGraphConfig& config) {
  const auto bounds = world.bounds();
  const MlsMap surveyed =
      survey_world(world, bounds.min.x(), bounds.min.y(), bounds.max.x(), bounds.max.y(), resolution);
  return PatchGraph(std::make_shared<const SurfaceGrid>(
                        surveyed, CellRegion::of_tiles(surveyed.tile_indices()), config.traversability),
                    resolution, config);
}

/// The same with `seen`'s configuration and resolution.
inline PatchGraph surveyed_graph(const sim::World& world, const PatchGraph& seen) {
  return surveyed_graph(world, seen.resolution(), seen.config());
}

/// Every place (on a grid of `spacing`) that the surveyed world `truth` says the robot can reach from
/// `robot` with room to spare (0.2 m beyond its radius: a wall scanned from afar is a cell thicker than
/// surveyed; the world's own end counts, where the simulator finds no ground: a campus goal 0.05 m from it
/// left the robot stuck there, unable to turn), and that the live map, as the graph `seen`, has measured
/// at that height (not inferred).
inline std::vector<Eigen::Vector3d> seen_goal_spots(const PatchGraph& truth, const PatchGraph& seen,
                                                    const Eigen::Vector3d& robot, double spacing = 0.5) {
  const auto robot_node = truth.locate(robot.x(), robot.y(), robot.z(), 0.5, 1.0);
  const std::uint32_t robot_component = robot_node ? truth.component(*robot_node) : PatchGraph::kNone;
  const int step = std::max(1, static_cast<int>(std::lround(spacing / seen.resolution())));
  std::vector<Eigen::Vector3d> spots;
  for (PatchGraph::Node node = 0; node < truth.node_count(); ++node) {
    const auto [col, row] = truth.cell(node);
    if (col % step != 0 || row % step != 0 || !truth.passable(node) ||
        truth.component(node) != robot_component ||
        static_cast<double>(truth.margin(node)) < seen.config().robot_radius + 0.2)
      continue;
    const Eigen::Vector3d spot = truth.position(node);
    const auto measured = seen.locate(spot.x(), spot.y(), spot.z(), 0.2);
    if (measured && !seen.inferred(*measured))
      spots.push_back(spot);
  }
  return spots;
}

/// Every seen goal spot (seen_goal_spots), planned to from `robot` on the live graph `seen`.
inline std::vector<SeenGoal> plan_to_seen_goals(const sim::World& world, const PatchGraph& seen,
                                                const Eigen::Vector3d& robot, double spacing = 0.5) {
  std::vector<SeenGoal> goals;
  for (const Eigen::Vector3d& goal : seen_goal_spots(surveyed_graph(world, seen), seen, robot, spacing)) {
    const auto start = std::chrono::steady_clock::now();
    PatchPath path = plan_on_patches(seen, robot, {.x = goal.x(), .y = goal.y(), .z = goal.z()});
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    goals.push_back({goal, std::hypot(goal.x() - robot.x(), goal.y() - robot.y()), std::move(path), ms});
  }
  return goals;
}

}  // namespace strata::test

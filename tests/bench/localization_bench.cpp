// Localization over a simulated run: the corrected trajectory against the ground truth, next to raw
// wheel odometry. Runs the simulator and the scan-to-map localizer synchronously (no server), so the
// numbers do not depend on the machine's speed. A benchmark: prints numbers, never fails on them.
// Usage: strata_localization_bench [world] [simulated seconds] [tilting|lidar]
// STRATA_BENCH_TRACE=1 prints every scan's error and verdict to stderr.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "core/localization/graph_localizer.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

using namespace strata;

namespace {
std::string eigen_text(const TranslationConstraint& c) {
  char text[160];
  std::snprintf(text, sizeof text, "%.3f(%.2f,%.2f,%.2f)/%.3f/%.3f rot %.3f(%.2f,%.2f,%.2f)/%.3f",
                c.eigenvalues[0], c.directions(0, 0), c.directions(1, 0), c.directions(2, 0),
                c.eigenvalues[1], c.eigenvalues[2], c.rotation_eigenvalues[0], c.rotation_axes(0, 0),
                c.rotation_axes(1, 0), c.rotation_axes(2, 0), c.rotation_eigenvalues[1]);
  return text;
}
}  // namespace

int main(int argc, char** argv) {
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double duration = argc > 2 ? std::atof(argv[2]) : 800.0;
  const std::string scanner = argc > 3 ? argv[3] : "tilting";
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));
  sim::SimulatorConfig config;
  config.scanner = scanner == "lidar" ? sim::ScannerKind::kLidar : sim::ScannerKind::kTilting;
  sim::Simulator simulator(world, config);
  const Eigen::Isometry3d map_from_odom =
      simulator.sample().truth->to_isometry() * simulator.sample().odometry.to_isometry().inverse();
  GraphLocalizerOptions graph_options;
  // STRATA_BENCH_POSE_GRAPH=0: the scan-to-map localizer alone, as before the pose graph.
  if (const char* graph = std::getenv("STRATA_BENCH_POSE_GRAPH"))
    graph_options.pose_graph = std::string(graph) != "0";
  LocalizerOptions& options = graph_options.scan_matching;
  // Variants, for measuring: STRATA_BENCH_METRIC=point|plane, STRATA_BENCH_LOCAL_MAP=<scans>,
  // STRATA_BENCH_LOCAL_VOXEL=<metres>.
  if (const char* metric = std::getenv("STRATA_BENCH_METRIC")) {
    options.registration.icp.metric =
        std::string(metric) == "point" ? IcpMetric::kPointToPoint : IcpMetric::kPointToPlane;
  }
  if (const char* n = std::getenv("STRATA_BENCH_LOCAL_MAP"))
    options.local_map_scans = std::strtoul(n, nullptr, 10);
  if (const char* voxel = std::getenv("STRATA_BENCH_LOCAL_VOXEL"))
    options.local_map_voxel = std::atof(voxel);
  GraphLocalizer localizer(graph_options, map_from_odom);
  double loop_seconds = 0.0;

  double travelled = 0.0, max_odometry_error = 0.0, max_corrected_error = 0.0, registration_seconds = 0.0;
  std::vector<double> times;
  std::vector<double> scan_times;  // the whole add_scan: local map, index, registration
  std::size_t scans = 0, full = 0, partial = 0, none = 0;
  Eigen::Vector3d last = simulator.sample().truth->position;
  double odometry_error = 0.0, corrected_error = 0.0;
  for (double t = 0.0; t < duration; t += 0.01) {
    simulator.step(0.01);
    const RobotSample s = simulator.sample();
    travelled += (s.truth->position - last).norm();
    last = s.truth->position;
    for (const ScanEvent& scan : simulator.take_scans()) {
      const Pose2 odometry{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw};
      const PointCloud points = pipeline::points_in_base(scan);
      const auto start = std::chrono::steady_clock::now();
      const LocalizationUpdate update = localizer.add_scan(points, odometry, scan.stamp);
      scan_times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      // The server runs this on a thread of its own; here it runs after each scan, so the numbers do not
      // depend on the machine's speed.
      const auto loop_start = std::chrono::steady_clock::now();
      localizer.close_loops();
      loop_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
      ++scans;
      if (update.registration) {
        times.push_back(update.registration->seconds);
        registration_seconds += update.registration->seconds;
      }
      update.correction == Correction::kFull      ? ++full
      : update.correction == Correction::kPartial ? ++partial
                                                  : ++none;
      if (std::getenv("STRATA_BENCH_TRACE") != nullptr) {
        const Eigen::Vector3d error = update.pose.translation() - scan.truth->position;
        std::fprintf(
            stderr, "t=%7.1f truth=(%6.1f %6.1f %5.2f) error=(%6.2f %6.2f %6.2f) %-8s %s eig=%s rmse=%.3f\n",
            scan.stamp, scan.truth->position.x(), scan.truth->position.y(), scan.truth->position.z(),
            error.x(), error.y(), error.z(), std::string(to_string(update.correction)).c_str(),
            update.registration ? std::string(to_string(update.registration->assessment.reason)).c_str()
                                : "-",
            update.registration ? eigen_text(update.registration->constraint).c_str() : "-",
            update.registration ? update.registration->rmse : 0.0);
      }
    }
    // Error of the pose the server would stream now: odometry carried by the latest correction.
    const Eigen::Isometry3d estimate =
        localizer.pose({s.odometry.position.x(), s.odometry.position.y(), s.odometry.yaw});
    const Eigen::Isometry3d raw = map_from_odom * s.odometry.to_isometry();
    corrected_error = (estimate.translation() - s.truth->position).norm();
    odometry_error = (raw.translation() - s.truth->position).head<2>().norm();  // odometry has no height
    max_corrected_error = std::max(max_corrected_error, corrected_error);
    max_odometry_error = std::max(max_odometry_error, odometry_error);
  }
  std::sort(times.begin(), times.end());
  std::sort(scan_times.begin(), scan_times.end());
  const PoseGraphStatus graph = localizer.status();
  std::size_t keyframe_points = 0;
  for (const auto& [keyframe, pose] : localizer.keyframes())
    keyframe_points += keyframe->points.size();
  // What the keyframes hold per kilometre driven: their points (Eigen::Vector3d, 24 bytes each).
  const double keyframe_mb_per_km =
      travelled > 0.0 ? static_cast<double>(keyframe_points) * 24.0 / 1e6 / (travelled / 1000.0) : 0.0;
  const auto pct_of = [](const std::vector<double>& sorted, double q) {
    return sorted.empty() ? 0.0
                          : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  const auto pct = [&](double q) { return pct_of(times, q); };
  std::printf(
      "{\"bench\":\"localization\",\"world\":\"%s\",\"scanner\":\"%s\",\"sim_seconds\":%.0f,\"travelled_m\":%"
      ".1f,"
      "\"scans\":%zu,\"full\":%zu,\"partial\":%zu,\"none\":%zu,"
      "\"final_error_m\":{\"corrected\":%.3f,\"odometry_xy\":%.3f},"
      "\"final_error_pct_of_distance\":{\"corrected\":%.2f,\"odometry_xy\":%.2f},"
      "\"max_error_m\":{\"corrected\":%.3f,\"odometry_xy\":%.3f},"
      "\"registration_ms\":{\"median\":%.1f,\"p95\":%.1f,\"max\":%.1f,\"mean\":%.1f},"
      "\"add_scan_ms\":{\"median\":%.1f,\"p95\":%.1f,\"max\":%.1f},"
      "\"pose_graph\":{\"on\":%s,\"keyframes\":%zu,\"loops\":%zu,\"loops_dropped\":%zu,\"optimizations\":%zu,"
      "\"background_s\":%.2f,\"keyframe_points\":%zu,\"keyframe_mb_per_km\":%.1f}}\n",
      world_name.c_str(), scanner.c_str(), duration, travelled, scans, full, partial, none, corrected_error,
      odometry_error, 100.0 * corrected_error / travelled, 100.0 * odometry_error / travelled,
      max_corrected_error, max_odometry_error, 1000 * pct(0.5), 1000 * pct(0.95), 1000 * pct(1.0),
      times.empty() ? 0.0 : 1000 * registration_seconds / static_cast<double>(times.size()),
      1000 * pct_of(scan_times, 0.5), 1000 * pct_of(scan_times, 0.95), 1000 * pct_of(scan_times, 1.0),
      graph_options.pose_graph ? "true" : "false", graph.keyframes, graph.loops, graph.loops_dropped,
      graph.optimizations, loop_seconds, keyframe_points, keyframe_mb_per_km);
  return 0;
}

// Localization over a simulated run: the corrected trajectory against the ground truth, next to raw
// wheel odometry. Runs the simulator and the scan-to-map localizer synchronously (no server), so the
// numbers do not depend on the machine's speed. A benchmark: prints numbers, never fails on them.
// Usage: strata_localization_bench [world] [simulated seconds] [tilting|lidar]
// STRATA_BENCH_TRACE=1 prints every scan's error and verdict to stderr.
// STRATA_BENCH_SEEDS=FIRST-LAST runs it once per simulator seed and then prints the errors over the seeds
// (mean and worst): one seed's maximum moves by 0.1-0.3 m for small changes (docs/benchmarks.md); with
// STRATA_BENCH_SECOND_RUN=1 each seed runs twice, the second from the IMU calibration the first kept.
//
// Map consistency ("revisit spread"): where two scans far apart along the way (>= 15 m driven) saw the
// same place (within 5 m), how far apart the map puts the same true point from the two: the walls a map
// doubles. For the live map, each scan at the pose it was mapped with; for the rebuilt map, each keyframe
// at its final pose graph estimate; "as_live", the map as the server has it when each scan comes (every
// optimization rebuilds it from the keyframes where the graph has them then). Keyframe tilt steps: how much
// the tilt error changes between consecutive keyframes, as the scan path mapped them and after the pose graph
// (floor far away doubles where it does); keyframe_tilt_max_deg: the largest tilt error of a keyframe after
// the pose graph. Loop measurements: each loop edge's relative pose against its two keyframes' true relative
// pose, the heading (signed: a mean off zero is a bias the loops hand to the map) and the position.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "core/localization/localizer.hpp"
#include "core/localization/pose_extrapolator.hpp"
#include "core/points/voxel_downsample.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/app/memory_policy.hpp"
#include "server/pipeline/map_rebuilder.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

using namespace strata;

namespace {

/// One scan (or keyframe) as the map has it: where it really was, where the map put it, what it saw.
struct Visit {
  Eigen::Isometry3d truth;
  Eigen::Isometry3d estimate;
  PointCloud points;  ///< base frame, thinned
  double travelled = 0.0;
  double stamp = 0.0;
};

struct Spread {
  std::size_t pairs = 0;
  double median = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};

/// Median, p95 and max of `values` (pairs: how many).
Spread spread_of(std::vector<double> values) {
  Spread spread;
  spread.pairs = values.size();
  if (values.empty())
    return spread;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) { return values[static_cast<std::size_t>(q * double(values.size() - 1))]; };
  spread.median = at(0.5);
  spread.p95 = at(0.95);
  spread.max = values.back();
  return spread;
}

/// Which way is up by the estimate when the truth's up is the map's: the tilt part of a pose's error.
Eigen::Vector3d error_up(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  return estimate.linear() * truth.linear().transpose() * Eigen::Vector3d::UnitZ();
}

/// The angle between two unit vectors, degrees.
double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

/// How the keyframes' tilt errors change from one keyframe to the next, degrees (median, p95, max): what
/// puts floor seen 20 m away at two heights in the map. A tilt error the keyframes share (the IMU's own)
/// tilts the whole map and does not count.
Spread keyframe_tilt_steps(const std::vector<KeyframePose>& keyframes, bool final_poses,
                           const std::map<double, Eigen::Isometry3d>& truth_at) {
  const auto up_of = [&](const KeyframePose& k) {
    return error_up(final_poses ? k.pose : k.keyframe->mapped_pose, truth_at.at(k.keyframe->stamp));
  };
  std::vector<double> steps;
  for (std::size_t i = 1; i < keyframes.size(); ++i)
    steps.push_back(degrees_between(up_of(keyframes[i - 1]), up_of(keyframes[i])));
  return spread_of(std::move(steps));
}

/// See the header comment. Per pair: the mean over the first visit's points within 10 m of its sensor.
Spread revisit_spread(const std::vector<Visit>& visits) {
  std::vector<double> spreads;
  for (std::size_t i = 0; i < visits.size(); ++i) {
    const Eigen::Isometry3d map_from_world_i = visits[i].estimate * visits[i].truth.inverse();
    for (std::size_t j = i + 1; j < visits.size(); ++j) {
      const Eigen::Vector3d apart = visits[j].truth.translation() - visits[i].truth.translation();
      if (visits[j].travelled - visits[i].travelled < 15.0 || apart.head<2>().norm() > 5.0 ||
          std::abs(apart.z()) > 1.0)
        continue;
      const Eigen::Isometry3d map_from_world_j = visits[j].estimate * visits[j].truth.inverse();
      double sum = 0.0;
      std::size_t n = 0;
      for (const Eigen::Vector3d& p : visits[i].points) {
        if (p.norm() > 10.0)
          continue;
        const Eigen::Vector3d world = visits[i].truth * p;
        sum += (map_from_world_i * world - map_from_world_j * world).norm();
        ++n;
      }
      if (n > 0)
        spreads.push_back(sum / static_cast<double>(n));
    }
  }
  return spread_of(std::move(spreads));
}

/// The map as the server has it when each scan comes: every earlier scan where the last rebuild put it
/// (its keyframe's optimized pose then, carrying the scan as the keyframe carries it), or where the scan
/// path mapped it since. Per scan, against the earlier scans the revisit rule pairs it with: the doubled
/// surfaces a goal's plan meets in the live map.
class AsLiveSpread {
 public:
  explicit AsLiveSpread(const std::vector<Visit>& visits) : visits_(visits) {}

  /// After each scan the server maps (the newest of `visits`).
  void scan_mapped() {
    const std::size_t j = visits_.size() - 1;
    live_.push_back(visits_[j].estimate);
    const Visit& newest = visits_[j];
    const Eigen::Isometry3d map_from_world_j = newest.estimate * newest.truth.inverse();
    for (std::size_t i = 0; i < j; ++i) {
      const Visit& old = visits_[i];
      const Eigen::Vector3d apart = newest.truth.translation() - old.truth.translation();
      if (newest.travelled - old.travelled < 15.0 || apart.head<2>().norm() > 5.0 ||
          std::abs(apart.z()) > 1.0)
        continue;
      const Eigen::Isometry3d map_from_world_i = live_[i] * old.truth.inverse();
      double sum = 0.0;
      std::size_t n = 0;
      for (const Eigen::Vector3d& p : old.points) {
        if (p.norm() > 10.0)
          continue;
        const Eigen::Vector3d world = old.truth * p;
        sum += (map_from_world_i * world - map_from_world_j * world).norm();
        ++n;
      }
      if (n > 0)
        spreads_.push_back(sum / static_cast<double>(n));
    }
  }

  /// After an optimization: the map is rebuilt from the keyframes where the graph now has them.
  void rebuilt(const std::vector<KeyframePose>& keyframes) {
    if (keyframes.empty())
      return;
    std::size_t k = 0;
    for (std::size_t i = 0; i < visits_.size(); ++i) {
      while (k + 1 < keyframes.size() && keyframes[k].keyframe->stamp < visits_[i].stamp)
        ++k;  // the keyframe that carries scan i: the first made at or after it
      const KeyframePose& owner = keyframes[k];
      live_[i] = owner.pose * owner.keyframe->mapped_pose.inverse() * visits_[i].estimate;
    }
  }

  [[nodiscard]] Spread spread() const { return spread_of(spreads_); }

 private:
  const std::vector<Visit>& visits_;
  std::vector<Eigen::Isometry3d> live_;
  std::vector<double> spreads_;
};

std::string eigen_text(const TranslationConstraint& c) {
  char text[160];
  std::snprintf(text, sizeof text, "%.3f(%.2f,%.2f,%.2f)/%.3f/%.3f rot %.3f(%.2f,%.2f,%.2f)/%.3f",
                c.eigenvalues[0], c.directions(0, 0), c.directions(1, 0), c.directions(2, 0),
                c.eigenvalues[1], c.eigenvalues[2], c.rotation_eigenvalues[0], c.rotation_axes(0, 0),
                c.rotation_axes(1, 0), c.rotation_axes(2, 0), c.rotation_eigenvalues[1]);
  return text;
}
/// How far ICP's own result (before any direction was taken from odometry) turned from the truth about
/// the vertical, degrees.
double icp_heading_error(const RegistrationResult& r, const Pose3& truth) {
  const Eigen::Matrix3d turn = r.refined.linear() * truth.to_isometry().linear().transpose();
  return std::atan2(turn(1, 0), turn(0, 0)) * 180.0 / M_PI;
}

/// STRATA_BENCH_SEEDS=FIRST-LAST: this bench again once per seed, each in a process of its own (the
/// simulator and the localizer start afresh), its JSON line passed on; then one line of the errors over
/// the seeds.
int run_seeds(int argc, char** argv, const std::string& seeds) {
  const std::size_t dash = seeds.find('-');
  const int first = std::atoi(seeds.c_str());
  const int last = dash == std::string::npos ? first : std::atoi(seeds.c_str() + dash + 1);
  if (first < 0 || last < first) {
    std::fprintf(stderr, "STRATA_BENCH_SEEDS=%s: expected FIRST-LAST, e.g. 1-10\n", seeds.c_str());
    return 2;
  }
  std::string command = "'" + std::string(argv[0]) + "'";
  for (int i = 1; i < argc; ++i)
    command += " '" + std::string(argv[i]) + "'";
  ::unsetenv("STRATA_BENCH_SEEDS");
  // Each measure: its values over the seeds.
  std::map<std::string, std::vector<double>> values;
  // One run of the bench as a child process: its lines passed on, its result returned.
  const auto run_child = [&](int seed) -> nlohmann::json {
    FILE* child = ::popen(command.c_str(), "r");
    if (child == nullptr) {
      std::perror("popen");
      return {};
    }
    nlohmann::json result;
    std::string line;
    for (int c = std::fgetc(child); c != EOF; c = std::fgetc(child)) {
      if (c != '\n') {
        line.push_back(static_cast<char>(c));
        continue;
      }
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
      const nlohmann::json run = nlohmann::json::parse(line, nullptr, false);
      if (!run.is_discarded() && run.value("bench", "") == "localization")
        result = run;
      line.clear();
    }
    if (::pclose(child) != 0)
      std::fprintf(stderr, "seed %d: the run failed\n", seed);
    return result;
  };
  // STRATA_BENCH_SECOND_RUN=1: each seed run twice, the second starting from the IMU mounting error the
  // first ended with (what the server keeps between runs, pipeline::ImuCalibrationStore); the errors are
  // the second run's.
  const char* second_run = std::getenv("STRATA_BENCH_SECOND_RUN");
  const bool twice = second_run != nullptr && std::string(second_run) == "1";
  ::unsetenv("STRATA_BENCH_SECOND_RUN");
  for (int seed = first; seed <= last; ++seed) {
    ::setenv("STRATA_BENCH_SEED", std::to_string(seed).c_str(), 1);
    ::unsetenv("STRATA_BENCH_START_MOUNTING_DEG");
    nlohmann::json run = run_child(seed);
    if (twice && run.contains("pose_graph")) {
      const nlohmann::json& kept = run["pose_graph"]["gravity_mounting_deg"];
      const std::string mounting =
          std::to_string(kept[0].get<double>()) + "," + std::to_string(kept[1].get<double>());
      ::setenv("STRATA_BENCH_START_MOUNTING_DEG", mounting.c_str(), 1);
      run = run_child(seed);
    }
    if (run.is_null())
      continue;
    values["final_error_m"].push_back(run["final_error_m"]["corrected"].get<double>());
    values["max_error_m"].push_back(run["max_error_m"]["corrected"].get<double>());
    values["max_height_error_m"].push_back(run["max_height_error_m"].get<double>());
    values["rebuilt_spread_p95_m"].push_back(run["revisit_spread_m"]["rebuilt_map"]["p95"].get<double>());
    values["registration_median_ms"].push_back(run["registration_ms"]["median"].get<double>());
  }
  nlohmann::json summary = {{"bench", "localization_seeds"},
                            {"seeds", std::to_string(first) + "-" + std::to_string(last)},
                            {"second_run", twice}};
  for (const auto& [name, list] : values) {
    double sum = 0.0;
    for (const double v : list)
      sum += v;
    const auto rounded = [](double v) { return std::round(v * 1000.0) / 1000.0; };
    summary[name] = {{"mean", rounded(sum / static_cast<double>(list.size()))},
                     {"worst", rounded(*std::max_element(list.begin(), list.end()))},
                     {"runs", list.size()}};
  }
  std::printf("%s\n", summary.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* seeds = std::getenv("STRATA_BENCH_SEEDS"))
    return run_seeds(argc, argv, seeds);
  strata::app::keep_freed_memory();  // as the server does: the scan path's buffers stay mapped
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double duration = argc > 2 ? std::atof(argv[2]) : 800.0;
  const std::string scanner = argc > 3 ? argv[3] : "tilting";
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));
  sim::SimulatorConfig config;
  if (const char* seed = std::getenv("STRATA_BENCH_SEED"))
    config.seed = std::strtoull(seed, nullptr, 10);
  config.scanner = scanner == "lidar" ? sim::ScannerKind::kLidar : sim::ScannerKind::kTilting;
  // STRATA_BENCH_IMU=0: a base without an IMU (wheels alone turn the odometry; no gravity with the scans).
  const bool imu =
      std::getenv("STRATA_BENCH_IMU") == nullptr || std::string(std::getenv("STRATA_BENCH_IMU")) != "0";
  if (!imu)
    config.imu.reset();
  // STRATA_BENCH_IMU_TILT_NOISE=<rad>: the accelerometer's noise while driving (and no mounting error when
  // 0): how much of the height error is the gravity readings'.
  if (const char* noise = std::getenv("STRATA_BENCH_IMU_TILT_NOISE"); noise && config.imu) {
    config.imu->tilt_noise_moving = std::atof(noise);
    if (config.imu->tilt_noise_moving == 0.0) {
      config.imu->tilt_bias_stddev = 0.0;
      config.imu->tilt_noise_standing = 0.0;
    }
  }
  // STRATA_BENCH_GYRO_NOISE=<rad/s^0.5>: the gyro's angle random walk, to tell how much of the heading error
  // is the gyro's noise (1e-7: next to none; 0 would leave the stands' readings without a sigma, unused).
  // The gravity readings draw from the same sequence: theirs differ.
  if (const char* noise = std::getenv("STRATA_BENCH_GYRO_NOISE"); noise && config.imu)
    config.imu->gyro_noise_density = std::atof(noise);
  // STRATA_BENCH_ODOMETRY=0: the localizer gets no odometry (a lidar alone: the constant velocity model).
  const bool with_odometry = std::getenv("STRATA_BENCH_ODOMETRY") == nullptr ||
                             std::string(std::getenv("STRATA_BENCH_ODOMETRY")) != "0";
  // STRATA_BENCH_DESKEW=0: a lidar's revolutions are registered as measured, smeared by the motion.
  const bool deskewing =
      std::getenv("STRATA_BENCH_DESKEW") == nullptr || std::string(std::getenv("STRATA_BENCH_DESKEW")) != "0";
  // STRATA_BENCH_GRAVITY=0: the gyro still turns the odometry, but the localizer gets no gravity.
  const bool gravity = std::getenv("STRATA_BENCH_GRAVITY") == nullptr ||
                       std::string(std::getenv("STRATA_BENCH_GRAVITY")) != "0";
  // STRATA_BENCH_STANDING_GYRO=0: the localizer gets no gyro reading of the stands (StandingGyro), and
  // fits the heading drift to the pose graph alone.
  const bool standing_gyro = std::getenv("STRATA_BENCH_STANDING_GYRO") == nullptr ||
                             std::string(std::getenv("STRATA_BENCH_STANDING_GYRO")) != "0";
  sim::Simulator simulator(world, config);
  const Eigen::Isometry3d map_from_odom =
      simulator.sample().truth->to_isometry() * simulator.sample().odometry.to_isometry().inverse();
  GraphLocalizerOptions graph_options;
  // STRATA_BENCH_POSE_GRAPH=0: the scan-to-map localizer alone, as before the pose graph.
  if (const char* graph = std::getenv("STRATA_BENCH_POSE_GRAPH"))
    graph_options.pose_graph = std::string(graph) != "0";
  if (const char* tilt = std::getenv("STRATA_BENCH_CHAIN_TILT"))  // the chain's roll and pitch sigma, rad
    graph_options.chain_sigma_tilt = std::atof(tilt);
  if (const char* tilt = std::getenv("STRATA_BENCH_CHAIN_TILT_PER_METRE"))  // rad per metre
    graph_options.chain_sigma_tilt_per_metre = std::atof(tilt);
  // STRATA_BENCH_HEIGHT_BEFORE_LOOPS=0: the scan path keeps its own height until the first loop (as before).
  if (const char* height = std::getenv("STRATA_BENCH_HEIGHT_BEFORE_LOOPS"))
    graph_options.height_before_loops = std::string(height) != "0";
  if (const char* yaw = std::getenv("STRATA_BENCH_CHAIN_YAW"))  // the chain's heading sigma, rad
    graph_options.chain_sigma_rotation = std::atof(yaw);
  if (const char* yaw = std::getenv("STRATA_BENCH_CHAIN_YAW_PER_METRE"))  // rad per metre
    graph_options.chain_sigma_rotation_per_metre = std::atof(yaw);
  // How sure the gyro's standing reading must be to replace the pose graph's fit of the drift, rad/s.
  if (const char* sigma = std::getenv("STRATA_BENCH_STANDING_SIGMA"))
    graph_options.heading_drift.standing_max_sigma = std::atof(sigma);
  if (const char* height = std::getenv("STRATA_BENCH_LOOP_HEIGHT"))  // metres between a loop's two keyframes
    graph_options.loops.max_height_difference = std::atof(height);
  if (const char* weak = std::getenv("STRATA_BENCH_LOOP_WEAK"))  // a loop edge's weak eigenvalue
    graph_options.loops.weak_direction = std::atof(weak);
  // STRATA_BENCH_LOOP_POLISH=0: the loops' point-to-point match as it stops, not finished point-to-plane.
  if (const char* polish = std::getenv("STRATA_BENCH_LOOP_POLISH"); polish && std::string(polish) == "0") {
    graph_options.loops.max_polish_translation = 0.0;
    graph_options.loops.max_polish_rotation = 0.0;
  }
  // STRATA_BENCH_EARLIER_PASS=<metres>: the earlier pass's keyframes within this join the local map (0: off).
  if (const char* radius = std::getenv("STRATA_BENCH_EARLIER_PASS"))
    graph_options.earlier_pass_radius = std::atof(radius);
  // STRATA_BENCH_MOUNTING_SIGMA=0: the graph does not estimate the IMU's mounting error (as before).
  if (const char* mounting = std::getenv("STRATA_BENCH_MOUNTING_SIGMA"))
    graph_options.optimizer.mounting_sigma = std::atof(mounting);
  LocalizerOptions& options = graph_options.scan_matching;
  // Variants, for measuring: STRATA_BENCH_METRIC=point|plane, STRATA_BENCH_LOCAL_MAP=<scans>,
  // STRATA_BENCH_LOCAL_METRES=<metres>, STRATA_BENCH_LOCAL_VOXEL=<metres>, STRATA_BENCH_SOURCE_POINTS=<n>,
  // STRATA_BENCH_FINE_VOXEL=<m>, STRATA_BENCH_COARSE_POINTS=<n>, STRATA_BENCH_ROTATION_GUARD=<eigenvalue>,
  // STRATA_BENCH_DIRECTION_GUARD=<eigenvalue>, STRATA_BENCH_SEED=<n>, STRATA_BENCH_SURFACE_SIDES=0,
  // STRATA_BENCH_TILT_DRIFT=<rad per scan>, STRATA_BENCH_BIAS_RATE=<per scan>, STRATA_BENCH_TILT_CHANGE=<rad
  // per metre>, STRATA_BENCH_SLIDING_YAW_DISTANCE=<metres>, STRATA_BENCH_ICP_STEP_STOP=<rad> (the scan path's
  // ICP stops on its step, 1e-4 m and this, instead of on the MSE's change), STRATA_BENCH_THREADS=<n> (the
  // registration's threads; 1 as before).
  if (const char* metric = std::getenv("STRATA_BENCH_METRIC")) {
    options.registration.icp.metric =
        std::string(metric) == "point" ? IcpMetric::kPointToPoint : IcpMetric::kPointToPlane;
  }
  if (const char* threads = std::getenv("STRATA_BENCH_THREADS"))  // the scan path's registration threads
    options.registration.icp.threads = static_cast<unsigned>(std::atoi(threads));
  if (const char* sides = std::getenv("STRATA_BENCH_SURFACE_SIDES"))  // 0: pairs across thin walls as before
    options.registration.icp.surface_sides.enabled = std::string(sides) != "0";
  if (const char* n = std::getenv("STRATA_BENCH_LOCAL_MAP"))
    options.local_map_scans = std::strtoul(n, nullptr, 10);
  if (const char* metres = std::getenv("STRATA_BENCH_LOCAL_METRES"))  // 0: by scan count alone, as before
    options.local_map_metres = std::atof(metres);
  if (const char* voxel = std::getenv("STRATA_BENCH_LOCAL_VOXEL"))
    options.local_map_voxel = std::atof(voxel);
  if (const char* voxel = std::getenv("STRATA_BENCH_FINE_VOXEL"))  // the fine stage's source voxel
    options.registration.stages.back().source_voxel_size = std::atof(voxel);
  if (const char* budget = std::getenv("STRATA_BENCH_SOURCE_POINTS"))  // 0: no budget
    options.registration.max_source_points = static_cast<std::size_t>(std::atol(budget));
  if (const char* drift = std::getenv("STRATA_BENCH_TILT_DRIFT"))
    options.gravity.drift_per_scan = std::atof(drift);
  if (const char* change = std::getenv("STRATA_BENCH_TILT_CHANGE"))
    options.gravity.tilt_change_per_metre = std::atof(change);
  if (const char* rate = std::getenv("STRATA_BENCH_BIAS_RATE"))
    options.gravity.bias_rate_per_radian = std::atof(rate);
  if (const char* points = std::getenv("STRATA_BENCH_COARSE_POINTS"))  // the coarse stage's own budget
    options.registration.stages.front().max_source_points = std::strtoul(points, nullptr, 10);
  if (const char* guard = std::getenv("STRATA_BENCH_ROTATION_GUARD"))
    options.weak_rotation_guard = std::atof(guard);
  if (const char* guard = std::getenv("STRATA_BENCH_DIRECTION_GUARD"))
    options.weak_direction_guard = std::atof(guard);
  if (const char* distance = std::getenv("STRATA_BENCH_SLIDING_YAW_DISTANCE"))
    options.sliding_yaw_distance = std::atof(distance);
  if (const char* step = std::getenv("STRATA_BENCH_ICP_STEP_STOP"))
    for (RegistrationStage& stage : options.registration.stages) {
      stage.mse_change_threshold = 0.0;
      stage.min_step_translation = 1e-4;
      stage.min_step_rotation = std::atof(step);
      stage.max_iterations = 60;
    }
  // Without odometry the localizer's odometry frame is its prediction's, which starts at the origin: the
  // map's start is then the true start itself.
  const Eigen::Isometry3d initial_correction =
      with_odometry ? map_from_odom : simulator.sample().truth->to_isometry();
  Localizer localizer(graph_options, initial_correction);
  // STRATA_BENCH_START_MOUNTING_DEG=<roll>,<pitch> (or "sim": the simulated IMU's own) and
  // STRATA_BENCH_START_DRIFT_DEG_PER_H=<rate> (or "sim": the gyro's bias, at the share of each scan's
  // seconds spent driving, 0.55): the run starts from that calibration (GraphLocalizer::
  // start_from_calibration), as a robot would from what an earlier run learnt.
  const char* start_mounting = std::getenv("STRATA_BENCH_START_MOUNTING_DEG");
  const char* start_drift = std::getenv("STRATA_BENCH_START_DRIFT_DEG_PER_H");
  if ((start_mounting || start_drift) && simulator.imu()) {
    Eigen::Vector3d mounting = Eigen::Vector3d::Zero();
    if (start_mounting && std::string(start_mounting) == "sim") {
      mounting = simulator.imu()->mounting_error();
    } else if (start_mounting) {
      double roll = 0.0;
      double pitch = 0.0;
      if (std::sscanf(start_mounting, "%lf,%lf", &roll, &pitch) != 2) {
        std::fprintf(stderr, "STRATA_BENCH_START_MOUNTING_DEG=%s: expected <roll>,<pitch> or sim\n",
                     start_mounting);
        return 2;
      }
      mounting = Eigen::Vector3d(roll, pitch, 0.0) * std::numbers::pi / 180.0;
    }
    double drift = 0.0;
    if (start_drift)
      drift = std::string(start_drift) == "sim" ? -simulator.imu()->gyro_bias() * 0.55
                                                : std::atof(start_drift) * std::numbers::pi / 180.0 / 3600.0;
    localizer.start_from_calibration(mounting, drift);
  }
  double loop_seconds = 0.0;
  // The pose the server streams between scans (RobotState): STRATA_BENCH_EXTRAPOLATE=0 measures the
  // odometry carried by the latest correction alone, without the base's gravity stream.
  const bool extrapolate = gravity && (std::getenv("STRATA_BENCH_EXTRAPOLATE") == nullptr ||
                                       std::string(std::getenv("STRATA_BENCH_EXTRAPOLATE")) != "0");
  PoseExtrapolator streamed;
  streamed.set_correction(initial_correction, std::nullopt);
  double max_height_error = 0.0;

  double travelled = 0.0, max_odometry_error = 0.0, max_corrected_error = 0.0, registration_seconds = 0.0;
  std::vector<double> times;
  std::vector<double> source_points;  // per registration, after thinning
  std::vector<double> scan_times;     // the whole Localizer::localize: local map, index, registration
  std::size_t scans = 0, full = 0, partial = 0, none = 0, retried = 0;
  // Scans by the localization state they left (ok, degraded, lost), and the largest error the state
  // called ok: how honest the status is.
  std::array<std::size_t, 3> in_state{};
  double max_error_while_ok = 0.0;
  Eigen::Vector3d last = simulator.sample().truth->position;
  std::vector<Visit> mapped;  // every scan the live map took, at the pose it took it with
  AsLiveSpread as_live(mapped);
  std::map<double, Eigen::Isometry3d> truth_at;  // by scan stamp
  double odometry_error = 0.0, corrected_error = 0.0;
  // A keyframe's heading error where the graph has it and the raw odometry's, against the truth, degrees:
  // what the heading drift is fitted to (STRATA_BENCH_HEADINGS, STRATA_BENCH_HEADINGS_AT).
  const auto print_heading_errors = [&](const char* prefix, const Keyframe& keyframe,
                                        const Eigen::Isometry3d& pose) {
    const double truth_heading = heading_of(truth_at.at(keyframe.stamp));
    std::fprintf(stderr,
                 "%skeyframe t=%.1f moving=%.1f graph_heading_error=%.3f odometry_heading_error=%.3f\n",
                 prefix, keyframe.stamp, keyframe.odometry_heading->seconds,
                 std::remainder(heading_of(pose) - truth_heading, 2.0 * M_PI) * 180.0 / M_PI,
                 std::remainder(keyframe.odometry_heading->odometry_heading - truth_heading, 2.0 * M_PI) *
                     180.0 / M_PI);
  };
  bool dumped = false;
  for (double t = 0.0; t < duration; t += 0.01) {
    simulator.step(0.01);
    const RobotSample s = simulator.sample();
    travelled += (s.truth->position - last).norm();
    last = s.truth->position;
    streamed.add_sample(s.stamp, with_odometry ? s.odometry : Pose3{},
                        extrapolate ? s.gravity : std::nullopt);
    for (const ScanEvent& scan : simulator.take_scans()) {
      const Pose2 odometry{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw};
      std::vector<float> point_times;
      PointCloud points = pipeline::points_in_base(scan, 0.3, &point_times);
      const auto start = std::chrono::steady_clock::now();
      const std::optional<Pose2> measured = with_odometry ? std::optional<Pose2>(odometry) : std::nullopt;
      ScanToLocalize to_localize{.points = std::move(points),
                                 .times = deskewing ? std::move(point_times) : std::vector<float>{},
                                 .stamp = scan.stamp,
                                 .odometry = measured,
                                 .sensor_origin = scan.sensor_to_base.translation(),
                                 .gravity = gravity ? scan.gravity : std::nullopt,
                                 .standing_gyro = standing_gyro ? scan.standing_gyro : std::nullopt};
      const LocalizedScan localized = localizer.localize(to_localize);
      const PointCloud& points_deskewed = to_localize.points;
      const LocalizationUpdate& update = localized.update;
      ++in_state[static_cast<std::size_t>(localized.health.state)];
      if (std::getenv("STRATA_BENCH_STATES") != nullptr)  // the state after each scan, and why
        std::fprintf(stderr, "t=%7.1f error=%.2f %s: %s\n", scan.stamp,
                     (update.pose.translation() - scan.truth->position).head<2>().norm(),
                     std::string(to_string(localized.health.state)).c_str(), localized.health.reason.c_str());
      if (localized.health.state == LocalizationState::kOk)
        max_error_while_ok =
            std::max(max_error_while_ok, (update.pose.translation() - scan.truth->position).head<2>().norm());
      streamed.set_mounting_error(localizer.gravity_mounting());
      streamed.set_correction(update.map_from_odom, scan.stamp);
      truth_at[scan.stamp] = scan.truth->to_isometry();
      if (!update.registration || update.correction != Correction::kNone) {
        mapped.push_back({scan.truth->to_isometry(), update.pose, voxel_downsample(points_deskewed, 0.5),
                          travelled, scan.stamp});
        as_live.scan_mapped();
      }
      scan_times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      // The server runs this on a thread of its own; here it runs after each scan, so the numbers do not
      // depend on the machine's speed.
      const auto loop_start = std::chrono::steady_clock::now();
      const std::size_t loops_before = localizer.graph_status().loops;
      const std::size_t optimizations_before = localizer.graph_status().optimizations;
      localizer.close_loops();
      if (localizer.graph_status().optimizations != optimizations_before)
        as_live.rebuilt(localizer.keyframes());
      loop_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
      if (std::getenv("STRATA_BENCH_TRACE") != nullptr && localizer.graph_status().loops != loops_before)
        std::fprintf(stderr, "loops %zu -> %zu at t=%.1f: the last moved its keyframe %.3f m\n", loops_before,
                     localizer.graph_status().loops, scan.stamp, localizer.graph_status().last_correction);
      // STRATA_BENCH_HEADINGS_AT=<t>: the keyframes' heading errors as the graph has them at t.
      if (const char* at = std::getenv("STRATA_BENCH_HEADINGS_AT");
          at && !dumped && scan.stamp >= std::atof(at)) {
        dumped = true;
        const std::string prefix = "at t=" + std::to_string(scan.stamp) + " ";
        for (const auto& [keyframe, pose] : localizer.keyframes())
          if (keyframe->odometry_heading)
            print_heading_errors(prefix.c_str(), *keyframe, pose);
      }
      ++scans;
      retried += update.retried ? 1 : 0;
      if (update.registration) {
        times.push_back(update.registration->seconds);
        source_points.push_back(static_cast<double>(update.registration->source_points));
        registration_seconds += update.registration->seconds;
      }
      update.correction == Correction::kFull      ? ++full
      : update.correction == Correction::kPartial ? ++partial
                                                  : ++none;
      if (std::getenv("STRATA_BENCH_TRACE") != nullptr) {
        const Eigen::Vector3d error = update.pose.translation() - scan.truth->position;
        // Rotation error about the map's axes, degrees: x and y are tilt, z heading.
        const Eigen::AngleAxisd turn(update.pose.linear() * scan.truth->to_isometry().linear().transpose());
        const Eigen::Vector3d turn_deg = turn.axis() * turn.angle() * 180.0 / M_PI;
        std::fprintf(
            stderr,
            "t=%7.1f yaw=%.3f truth=(%7.3f %7.3f %6.3f) error=(%6.2f %6.2f %6.2f) rot=(%5.2f %5.2f %5.2f) "
            "%-8s %s eig=%s "
            "rmse=%.3f icp_yaw=%.3f yaw_info=%.4f drift=%.2f odometry_yaw=%.3f mounting=(%.3f %.3f) "
            "leveling_mounting=(%.3f %.3f) pairs=%zu/%zu target=%zu\n",
            scan.stamp, scan.truth->yaw * 180.0 / M_PI, scan.truth->position.x(), scan.truth->position.y(),
            scan.truth->position.z(), error.x(), error.y(), error.z(), turn_deg.x(), turn_deg.y(),
            turn_deg.z(), std::string(to_string(update.correction)).c_str(),
            update.registration ? std::string(to_string(update.registration->assessment.reason)).c_str()
                                : "-",
            update.registration ? eigen_text(update.registration->constraint).c_str() : "-",
            update.registration ? update.registration->rmse : 0.0,
            update.registration ? icp_heading_error(*update.registration, *scan.truth) : 0.0,
            update.registration
                ? rotation_information(update.registration->constraint, Eigen::Vector3d::UnitZ())
                : 0.0,
            localizer.graph_status().heading_drift_deg_per_h(),
            // The odometry's own heading error (its drift so far), degrees.
            std::remainder(heading_of(map_from_odom * scan.odometry.to_isometry()) - scan.truth->yaw,
                           2.0 * M_PI) *
                180.0 / M_PI,
            localizer.graph_status().gravity_mounting_deg().x(),
            localizer.graph_status().gravity_mounting_deg().y(),
            localizer.gravity_mounting().x() * 180.0 / M_PI, localizer.gravity_mounting().y() * 180.0 / M_PI,
            update.registration ? update.registration->pairs : 0,
            update.registration ? update.registration->source_points : 0,
            update.registration ? update.registration->target_points : 0);
      }
    }
    // Error of the pose the server would stream now.
    const Eigen::Isometry3d estimate = streamed.estimate().to_isometry();
    const Eigen::Isometry3d raw = map_from_odom * s.odometry.to_isometry();
    corrected_error = (estimate.translation() - s.truth->position).norm();
    odometry_error = (raw.translation() - s.truth->position).head<2>().norm();  // odometry has no height
    max_corrected_error = std::max(max_corrected_error, corrected_error);
    max_height_error =
        std::max(max_height_error, std::abs(estimate.translation().z() - s.truth->position.z()));
    max_odometry_error = std::max(max_odometry_error, odometry_error);
  }
  std::sort(times.begin(), times.end());
  std::sort(scan_times.begin(), scan_times.end());
  const PoseGraphStatus graph = localizer.graph_status();
  const std::vector<KeyframePose> keyframes = localizer.keyframes();
  std::size_t keyframe_points = 0, keyframe_map_points = 0;
  std::vector<Visit> rebuilt;  // the keyframes at their final estimates: what the rebuilt map has
  for (const auto& [keyframe, pose] : keyframes) {
    keyframe_points += keyframe->points.size();
    for (const KeyframeScan& scan : keyframe->scans)
      keyframe_map_points += scan.points.size();
    rebuilt.push_back(
        {truth_at.at(keyframe->stamp), pose, voxel_downsample(keyframe->points, 0.5), keyframe->travelled});
    if (std::getenv("STRATA_BENCH_HEADINGS") != nullptr && keyframe->odometry_heading)
      print_heading_errors("", *keyframe, pose);
  }
  // What the keyframes hold per kilometre driven: their registration points (Eigen::Vector3d, 24 bytes
  // each) and their map points (Eigen::Vector3f, 12 bytes).
  const double km = travelled / 1000.0;
  const double keyframe_mb_per_km =
      travelled > 0.0 ? static_cast<double>(keyframe_points) * 24.0 / 1e6 / km : 0.0;
  const double map_mb_per_km =
      travelled > 0.0 ? static_cast<double>(keyframe_map_points) * 12.0 / 1e6 / km : 0.0;
  // The rebuild the mapping worker does after an optimization, here once over all keyframes.
  const auto rebuild_start = std::chrono::steady_clock::now();
  const MlsMap rebuilt_map = pipeline::MapRebuilder(MlsConfig{}).build(keyframes);
  const double rebuild_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - rebuild_start).count();
  const Spread live_spread = revisit_spread(mapped);
  const Spread rebuilt_spread = revisit_spread(rebuilt);
  const Spread as_live_spread = as_live.spread();
  const Spread path_tilt = keyframe_tilt_steps(keyframes, false, truth_at);
  const Spread graph_tilt = keyframe_tilt_steps(keyframes, true, truth_at);
  double max_keyframe_tilt = 0.0;
  for (const auto& [keyframe, pose] : keyframes)
    max_keyframe_tilt =
        std::max(max_keyframe_tilt,
                 degrees_between(error_up(pose, truth_at.at(keyframe->stamp)), Eigen::Vector3d::UnitZ()));
  // What the loops measured against the truth.
  double loop_heading_sum = 0.0, loop_heading_abs_sum = 0.0, loop_heading_worst = 0.0;
  std::vector<double> loop_position_errors;
  for (const PoseGraphEdge& loop : localizer.loops()) {
    const Eigen::Isometry3d truth = truth_at.at(keyframes[loop.from].keyframe->stamp).inverse() *
                                    truth_at.at(keyframes[loop.to].keyframe->stamp);
    const Eigen::Isometry3d error = truth.inverse() * loop.measurement;
    const double heading = heading_of(error) * 180.0 / std::numbers::pi;
    if (std::getenv("STRATA_BENCH_TRACE") != nullptr) {
      // The position error turned into the map's axes; the information's diagonal (x y z, then rotation).
      const Eigen::Vector3d in_map =
          truth_at.at(keyframes[loop.to].keyframe->stamp).linear() * error.translation();
      std::string diagonal;
      for (int k = 0; k < 6; ++k)
        diagonal += (k ? "," : "") + std::to_string(loop.information(k, k));
      std::fprintf(stderr,
                   "loop_edge %.1f -> %.1f heading_error=%.3f position_error=%.3f map_error=(%.3f %.3f %.3f) "
                   "information=%s\n",
                   keyframes[loop.from].keyframe->stamp, keyframes[loop.to].keyframe->stamp, heading,
                   error.translation().norm(), in_map.x(), in_map.y(), in_map.z(), diagonal.c_str());
    }
    loop_heading_sum += heading;
    loop_heading_abs_sum += std::abs(heading);
    loop_heading_worst = std::max(loop_heading_worst, std::abs(heading));
    loop_position_errors.push_back(error.translation().norm());
  }
  std::sort(loop_position_errors.begin(), loop_position_errors.end());
  const double loop_count = static_cast<double>(std::max<std::size_t>(1, loop_position_errors.size()));
  const auto pct_of = [](const std::vector<double>& sorted, double q) {
    return sorted.empty() ? 0.0
                          : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  const auto pct = [&](double q) { return pct_of(times, q); };
  std::sort(source_points.begin(), source_points.end());
  std::printf(
      "{\"bench\":\"localization\",\"world\":\"%s\",\"scanner\":\"%s\",\"sim_seconds\":%.0f,\"travelled_m\":%"
      ".1f,"
      "\"scans\":%zu,\"full\":%zu,\"partial\":%zu,\"none\":%zu,\"retried\":%zu,"
      "\"state_scans\":{\"ok\":%zu,\"degraded\":%zu,\"lost\":%zu},\"max_error_while_ok_m\":%.3f,"
      "\"final_error_m\":{\"corrected\":%.3f,\"odometry_xy\":%.3f},"
      "\"final_error_pct_of_distance\":{\"corrected\":%.2f,\"odometry_xy\":%.2f},"
      "\"max_error_m\":{\"corrected\":%.3f,\"odometry_xy\":%.3f},\"max_height_error_m\":%.3f,"
      "\"registration_ms\":{\"median\":%.1f,\"p95\":%.1f,\"max\":%.1f,\"mean\":%.1f},"
      "\"add_scan_ms\":{\"median\":%.1f,\"p95\":%.1f,\"max\":%.1f},\"source_points_median\":%.0f,"
      "\"pose_graph\":{\"on\":%s,\"keyframes\":%zu,\"loops\":%zu,\"loops_dropped\":%zu,\"optimizations\":%zu,"
      "\"earlier_pass_joins\":%zu,\"background_s\":%.2f,\"heading_drift_deg_per_h\":%.2f,\"sim_gyro_drift_deg_per_h\":%.2f,"
      "\"gravity_mounting_deg\":[%.3f,%.3f],\"sim_gravity_mounting_deg\":[%.3f,%.3f],"
      "\"keyframe_points\":%zu,\"keyframe_mb_per_km\":"
      "%.1f,"
      "\"keyframe_map_points\":%zu,\"keyframe_map_mb_per_km\":%.1f,\"rebuild_s\":%.2f,\"rebuilt_patches\":%"
      "zu},"
      "\"revisit_spread_m\":{\"live_map\":{\"pairs\":%zu,\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f},"
      "\"rebuilt_map\":{\"pairs\":%zu,\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f},"
      "\"as_live\":{\"pairs\":%zu,\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f}},"
      "\"keyframe_tilt_step_deg\":{\"scan_path\":{\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f},"
      "\"graph\":{\"median\":%.3f,\"p95\":%.3f,\"max\":%.3f}},\"keyframe_tilt_max_deg\":%.3f,"
      "\"loop_measurement\":{\"heading_error_deg\":{\"mean\":%.3f,\"mean_abs\":%.3f,\"max_abs\":%.3f},"
      "\"position_error_m\":{\"median\":%.3f,\"max\":%.3f}}}\n",
      world_name.c_str(), scanner.c_str(), duration, travelled, scans, full, partial, none, retried,
      in_state[0], in_state[1], in_state[2], max_error_while_ok, corrected_error, odometry_error,
      100.0 * corrected_error / travelled, 100.0 * odometry_error / travelled, max_corrected_error,
      max_odometry_error, max_height_error, 1000 * pct(0.5), 1000 * pct(0.95), 1000 * pct(1.0),
      times.empty() ? 0.0 : 1000 * registration_seconds / static_cast<double>(times.size()),
      1000 * pct_of(scan_times, 0.5), 1000 * pct_of(scan_times, 0.95), 1000 * pct_of(scan_times, 1.0),
      pct_of(source_points, 0.5), graph_options.pose_graph ? "true" : "false", graph.keyframes, graph.loops,
      graph.loops_dropped, graph.optimizations, graph.earlier_pass_joins, loop_seconds, graph.heading_drift_deg_per_h(),
      simulator.imu() ? -simulator.imu()->gyro_bias() * 180.0 / M_PI * 3600.0 : 0.0,
      graph.gravity_mounting_deg().x(), graph.gravity_mounting_deg().y(),
      simulator.imu() ? simulator.imu()->mounting_error().x() * 180.0 / M_PI : 0.0,
      simulator.imu() ? simulator.imu()->mounting_error().y() * 180.0 / M_PI : 0.0, keyframe_points,
      keyframe_mb_per_km, keyframe_map_points, map_mb_per_km, rebuild_seconds, rebuilt_map.patch_count(),
      live_spread.pairs, live_spread.median, live_spread.p95, live_spread.max, rebuilt_spread.pairs,
      rebuilt_spread.median, rebuilt_spread.p95, rebuilt_spread.max, as_live_spread.pairs,
      as_live_spread.median, as_live_spread.p95, as_live_spread.max, path_tilt.median, path_tilt.p95,
      path_tilt.max, graph_tilt.median, graph_tilt.p95, graph_tilt.max, max_keyframe_tilt,
      loop_heading_sum / loop_count, loop_heading_abs_sum / loop_count, loop_heading_worst,
      pct_of(loop_position_errors, 0.5), pct_of(loop_position_errors, 1.0));
  return 0;
}

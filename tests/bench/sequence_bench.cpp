// Real lidar sequences with a reference trajectory through the real scan path (issue 58 item 1): the
// replay driver, the localizer and the mapping worker of `strata serve --replay DIR --replay-odometry none`
// (RobotPipeline, without the network), paced as fast as the pipeline takes the scans (none dropped) or by
// the recorded clock (a busy localizer drops scans, as on a robot). Prints a line per processed scan (time,
// verdict, localization state, CPU, errors against the reference: horizontal, 3D, the height signed, the
// offset along and across the reference's heading, and the tilt as pitch and roll in the reference's body
// frame) and a JSON summary: maximum horizontal and 3D error, heading, relative error per 10 m, KITTI-style
// drift, scans dropped, whether the track was ever lost. A benchmark: prints numbers, never fails on them.
//
// Usage: strata_sequence_bench DIR [--pace max|recorded] [--time-scale X] [--mount estimate|identity]
//        [--every N] [--quiet]   (--every N: every n-th scan only: scans dropped, turns n times as sharp)
//        [--odometry none|recorded] [--save-map FILE] [--threads N]
//   --odometry recorded: the dataset's odometry (a recording's odometry.csv, e.g. `strata serve --record`
//                        of the simulator), instead of the lidar alone
//   --save-map FILE: the map at the end, as Download "strata" gives it (for strata_live_navigation_bench
//   --map)
//   --threads N: the registration's threads (default the server's two); the CPU a scan printed is the
//                localizer thread's own, so --threads 1 is a scan's whole cost on one core
//        strata_sequence_bench --all [--data DIR] [options]: every sequence in DATA/sequences
//        strata_sequence_bench DIR --lay-out OUT: only writes OUT/scans.csv, for `strata serve --replay OUT`
//        strata_sequence_bench DIR --direct: each scan registered straight onto the first and the chain of
//        consecutive pairs, against the reference: whose tilt drifts, the reference's or a chain's
// DIR: a scans.csv with truth_* columns, or a layout of ../shared/data/sequences
// (tests/support/sequence_layout.hpp).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/trajectory_errors.hpp"
#include "core/registration/register_scan.hpp"
#include "drivers/replay/dataset.hpp"
#include "drivers/replay/replay_driver.hpp"
#include "server/app/memory_policy.hpp"
#include "server/pipeline/robot_pipeline.hpp"
#include "support/sequence_layout.hpp"

using namespace strata;
namespace fs = std::filesystem;

namespace {

struct Settings {
  bool recorded_pace = false;
  double time_scale = 1.0;
  bool estimate_mount = true;  // as a scans.csv without mount columns replays
  bool quiet = false;
  std::size_t every = 1;  // keep every n-th scan
  bool recorded_odometry = false;
  std::string save_map;             // empty: not saved
  std::optional<unsigned> threads;  // the registration's; empty: the server's default (two)
};

/// What the pipeline's observer saw, on the localizer's thread.
struct Observed {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<pipeline::LocalizerWorker::ScanReport> outcomes;
};

double median(std::vector<double> values) {
  if (values.empty())
    return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

void run(const fs::path& dir, const Settings& settings, bool first) {
  const fs::path scratch = fs::temp_directory_path() / ("strata-sequence-" + std::to_string(::getpid()));
  const fs::path list = test::scan_list_for(dir, scratch, settings.every);
  replay::ReplayOptions options;
  options.pacing = {.time_scale = settings.time_scale, .as_fast_as_possible = !settings.recorded_pace};
  options.odometry =
      settings.recorded_odometry ? replay::OdometrySource::kDataset : replay::OdometrySource::kNone;
  if (!settings.estimate_mount)
    options.mount = Eigen::Isometry3d::Identity();
  replay::Dataset dataset = replay::open_dataset(list);
  const std::size_t scans = dataset.scans.size();
  auto driver = std::make_unique<replay::ReplayDriver>(std::move(dataset), options);
  const replay::ReplayDriver& replay = *driver;

  Observed observed;
  pipeline::PipelineOptions pipeline_options;
  pipeline_options.maps_dir = scratch / "maps";  // nothing is saved there
  pipeline_options.registration_threads = settings.threads;
  pipeline::RobotPipeline robot(std::move(driver), {}, pipeline_options);
  robot.on_scan_localized([&observed](const pipeline::LocalizerWorker::ScanReport& outcome) {
    std::lock_guard lock(observed.mutex);
    observed.outcomes.push_back(outcome);
    observed.changed.notify_all();
  });
  const auto start = std::chrono::steady_clock::now();
  robot.start();
  {
    // Until the replay has played everything and the localizer has been quiet for a second after it.
    std::unique_lock lock(observed.mutex);
    std::size_t seen = 0;
    while (!replay.finished() || observed.outcomes.size() != seen) {
      seen = observed.outcomes.size();
      observed.changed.wait_for(lock, std::chrono::seconds(1));
      if (observed.outcomes.size() == scans)
        break;
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!settings.save_map.empty()) {
    const MapDownload map = robot.services().maps->download("strata", std::nullopt);
    std::ofstream(settings.save_map, std::ios::binary)
        .write(reinterpret_cast<const char*>(map.bytes.data()),
               static_cast<std::streamsize>(map.bytes.size()));
  }
  robot.stop();
  fs::remove_all(scratch);

  std::vector<bench::TrackedPose> track;
  std::vector<double> cpu_ms;
  std::size_t full = 0, partial = 0, kept = 0, lost = 0, degraded = 0;
  for (std::size_t i = 0; i < observed.outcomes.size(); ++i) {
    const auto& o = observed.outcomes[i];
    cpu_ms.push_back(o.cpu_ms);
    full += o.correction == Correction::kFull ? 1 : 0;
    partial += o.correction == Correction::kPartial ? 1 : 0;
    kept += o.registered && o.correction == Correction::kNone ? 1 : 0;
    lost += o.state == LocalizationState::kLost ? 1 : 0;
    degraded += o.state == LocalizationState::kDegraded ? 1 : 0;
    if (!o.truth)
      continue;
    track.push_back({o.stamp, o.pose, o.truth->to_isometry()});
    if (!settings.quiet) {
      const Eigen::Vector3d offset = o.pose.translation() - track.back().reference.translation();
      // The tilt error as the estimate's up axis seen in the reference's body frame: x is pitch, y is roll.
      const Eigen::Vector3d up_seen = track.back().reference.linear().transpose() * o.pose.linear().col(2);
      constexpr double kDeg = 180.0 / 3.141592653589793;
      // The offset along the reference's heading and across it: a pose taken at another moment of the
      // sweep is off along the way, by the speed times the time between.
      const Eigen::Vector3d in_body = track.back().reference.linear().transpose() * offset;
      std::fprintf(stderr,
                   "%s scan %zu t=%.3f cpu %.1f ms %s rmse %.3f m %s horizontal %.3f m 3d %.3f m dz %+.3f m "
                   "along %+.3f across %+.3f m tilt %+.2f %+.2f deg\n",
                   dir.filename().c_str(), i, o.stamp, o.cpu_ms,
                   o.registered ? std::string(to_string(o.correction)).c_str() : "first", o.rmse,
                   std::string(to_string(o.state)).c_str(), offset.head<2>().norm(), offset.norm(),
                   offset.z(), in_body.x(), in_body.y(), std::asin(up_seen.x()) * kDeg,
                   std::asin(up_seen.y()) * kDeg);
    }
  }
  const bench::TrajectoryErrors errors = bench::trajectory_errors(track);
  std::printf(
      "%s  {\"sequence\": \"%s\", \"every\": %zu, \"pace\": \"%s\", \"time_scale\": %.2f, \"mount\": \"%s\", "
      "\"scans\": %zu, "
      "\"processed\": %zu, \"dropped\": %zu, \"full\": %zu, \"partial\": %zu, \"kept_prediction\": %zu, "
      "\"degraded_scans\": %zu, \"lost_scans\": %zu, \"ever_lost\": %s, \"path_m\": %.2f, "
      "\"max_horizontal_m\": %.3f, \"max_3d_m\": "
      "%.3f, "
      "\"final_horizontal_m\": %.3f, \"max_heading_deg\": %.2f, \"relative_per_10m_mean_m\": %.3f, "
      "\"relative_per_10m_max_m\": %.3f, \"drift_percent\": %.2f, \"cpu_ms_median\": %.1f, \"wall_s\": %.1f}",
      first ? "" : ",\n", dir.filename().c_str(), settings.every, settings.recorded_pace ? "recorded" : "max",
      settings.time_scale, settings.estimate_mount ? "estimate" : "identity", scans, observed.outcomes.size(),
      scans - std::min(scans, observed.outcomes.size()), full, partial, kept, degraded, lost,
      lost > 0 ? "true" : "false", errors.path_m, errors.max_horizontal_m, errors.max_3d_m,
      errors.final_horizontal_m, errors.max_heading_deg, errors.relative_per_10m_mean_m,
      errors.relative_per_10m_max_m, errors.drift_percent, median(cpu_ms), wall_s);
  std::fflush(stdout);
}

/// A third opinion on the reference's tilt (`--direct`): scan k registered straight onto scan 0 from the
/// reference's relative pose, and the chain of consecutive pairs registered the same way, against the
/// reference. A lidar-odometry reference (A-LOAM's for KAIST03) drifts as the scan path may: the direct
/// registration shares no step with either. Prints, per k, each estimate's rotation from the reference's
/// (degrees about scan 0's x and y axes) and its position's offset, in metres.
void direct_check(const fs::path& dir, std::size_t every) {
  const fs::path scratch = fs::temp_directory_path() / ("strata-sequence-" + std::to_string(::getpid()));
  const replay::Dataset dataset = replay::open_dataset(test::scan_list_for(dir, scratch, every));
  const auto cloud = [&](std::size_t i) {
    PointCloud points;
    for (const Eigen::Vector3f& p : replay::load_points(dataset.scans[i]))
      points.push_back(p.cast<double>());
    return points;
  };
  const auto reference = [&](std::size_t i) { return dataset.scans[i].reference->to_isometry(); };
  const auto print = [](const char* what, std::size_t k, const Eigen::Isometry3d& estimate,
                        const Eigen::Isometry3d& truth, const RegistrationResult* result) {
    const Eigen::AngleAxisd turn(estimate.linear() * truth.linear().transpose());
    const Eigen::Vector3d degrees = turn.axis() * turn.angle() * 180.0 / M_PI;
    std::printf("%s scan %zu about_x %+.3f about_y %+.3f deg offset %.3f m dz %+.3f m", what, k, degrees.x(),
                degrees.y(), (estimate.translation() - truth.translation()).norm(),
                estimate.translation().z() - truth.translation().z());
    if (result != nullptr)
      std::printf(" rmse %.3f pairs %zu", result->rmse, result->pairs);
    std::printf("\n");
  };
  if (dataset.scans.empty() || std::any_of(dataset.scans.begin(), dataset.scans.end(),
                                           [](const auto& scan) { return !scan.reference; }))
    throw std::runtime_error("--direct needs a reference pose for every scan");
  const PointCloud first = cloud(0);
  Eigen::Isometry3d chain = Eigen::Isometry3d::Identity();
  PointCloud previous = first;
  for (std::size_t k = 1; k < dataset.scans.size(); ++k) {
    const PointCloud scan = cloud(k);
    const Eigen::Isometry3d truth = reference(0).inverse() * reference(k);
    const RegistrationResult direct = register_scan(scan, first, truth);
    const Eigen::Isometry3d step_truth = reference(k - 1).inverse() * reference(k);
    const RegistrationResult step = register_scan(scan, previous, step_truth);
    chain = chain * step.refined;
    print("direct", k, direct.refined, truth, &direct);
    print("chain", k, chain, truth, nullptr);
    previous = scan;
  }
  fs::remove_all(scratch);
}

int usage() {
  std::fprintf(
      stderr,
      "usage: strata_sequence_bench DIR|--all [--data DIR] [--pace max|recorded] [--time-scale X] "
      "[--mount estimate|identity] [--every N] [--threads N] [--quiet] [--lay-out OUT] [--direct]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  strata::app::keep_freed_memory();  // as the server does
  spdlog::set_default_logger(spdlog::stderr_color_mt("bench"));
  spdlog::set_level(spdlog::level::warn);
  Settings settings;
  fs::path data = STRATA_DATA_DIR;
  std::vector<fs::path> dirs;
  bool all = false;
  bool direct = false;
  std::optional<fs::path> lay_out;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--all")
      all = true;
    else if (arg == "--quiet")
      settings.quiet = true;
    else if (arg == "--direct")
      direct = true;
    else if (arg == "--every" && has_value)
      settings.every = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
    else if (arg == "--threads" && has_value)
      settings.threads = static_cast<unsigned>(std::max(1, std::atoi(argv[++i])));
    else if (arg == "--lay-out" && has_value)
      lay_out = argv[++i];
    else if (arg == "--data" && has_value)
      data = argv[++i];
    else if (arg == "--pace" && has_value)
      settings.recorded_pace = std::string(argv[++i]) == "recorded";
    else if (arg == "--time-scale" && has_value)
      settings.time_scale = std::atof(argv[++i]);
    else if (arg == "--odometry" && has_value)
      settings.recorded_odometry = std::string(argv[++i]) == "recorded";
    else if (arg == "--save-map" && has_value)
      settings.save_map = argv[++i];
    else if (arg == "--mount" && has_value)
      settings.estimate_mount = std::string(argv[++i]) != "identity";
    else if (!arg.starts_with("--"))
      dirs.emplace_back(arg);
    else
      return usage();
  }
  if (all) {
    if (!fs::is_directory(data / "sequences")) {
      std::fprintf(stderr, "strata_sequence_bench: no %s: skipped\n", (data / "sequences").c_str());
      return 0;
    }
    for (const auto& entry : fs::directory_iterator(data / "sequences")) {
      if (entry.is_directory())
        dirs.push_back(entry.path());
    }
    std::sort(dirs.begin(), dirs.end());
  }
  if (dirs.empty())
    return usage();
  if (lay_out) {
    const fs::path list = test::scan_list_for(dirs.front(), *lay_out, settings.every);
    std::printf("%s\n", (list / "scans.csv").c_str());
    return 0;
  }
  if (direct) {
    for (const fs::path& dir : dirs)
      direct_check(dir, settings.every);
    return 0;
  }
  std::printf("[\n");
  bool first = true;
  for (const fs::path& dir : dirs) {
    try {
      run(dir, settings, first);
      first = false;
    } catch (const std::exception& error) {
      std::fprintf(stderr, "strata_sequence_bench: %s: %s\n", dir.c_str(), error.what());
    }
  }
  std::printf("\n]\n");
  return 0;
}

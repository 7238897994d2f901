// Every real capture and scan sequence in the data directory through the scan path as a lidar alone
// (issue 23 item 4): the sensor's mount estimated from the ground, each scan registered without odometry
// (GraphLocalizer with its constant velocity prediction) and mapped into an MLS map, one thread, no server.
// Prints JSON per capture: scans, registered (fully, partly), rejected, the estimated mount, the time per
// scan of registration and of mapping (median, max), and for the 3DTK scans the last pose's distance from
// slam6D's reference. --maps DIR saves each map (strata map export, or load it in `strata serve`).
// A benchmark: prints numbers, never fails on them. Skips what is not in the data directory.
// Usage: strata_real_capture_bench [--data DIR] [--maps DIR] [--repeat N]
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/localization/graph_localizer.hpp"
#include "core/mls/mls_file.hpp"
#include "core/mls/mls_map.hpp"
#include "drivers/lidar/pcap_scan_source.hpp"
#include "drivers/replay/dataset.hpp"
#include "drivers/sensor_mount.hpp"
#include "server/app/memory_policy.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

using namespace strata;
namespace fs = std::filesystem;

namespace {

struct Capture {
  std::string name;
  std::vector<ScanEvent> scans;
  std::optional<Eigen::Isometry3d> last_reference;  ///< the last scan's reference pose, where there is one
};

double median(std::vector<double> values) {
  if (values.empty())
    return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double max_of(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// This thread's CPU time, ms: what one core spends, whatever else the machine runs meanwhile (wall time on
/// a shared 2-core machine varies 20-50 % from run to run).
double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

std::optional<Capture> read_pcap(const fs::path& dir, const std::string& file, lidar::LidarModel model,
                                 const std::string& calibration, bool keep_partial) {
  if (!fs::exists(dir / file))
    return std::nullopt;
  Capture capture{file, {}, std::nullopt};
  lidar::PcapScanSource source(dir / file, lidar::LidarSetup{model, dir / calibration, 0, keep_partial});
  while (std::optional<ScanEvent> scan = source.next())
    capture.scans.push_back(std::move(*scan));
  return capture;
}

std::optional<Capture> read_3dtk(const fs::path& dir) {
  if (!fs::exists(dir / "scan000.3d"))
    return std::nullopt;
  const replay::Dataset dataset = replay::open_dataset(dir);
  Capture capture{"3dtk_dat", {}, std::nullopt};
  for (const replay::DatasetScan& source : dataset.scans) {
    ScanEvent scan;
    scan.stamp = source.stamp;
    scan.points = replay::load_points(source);
    scan.sensor = source.sensor;
    capture.scans.push_back(std::move(scan));
  }
  // Poses relative to the first scan's reference, as the localizer starts at the origin.
  if (dataset.scans.front().reference && dataset.scans.back().reference)
    capture.last_reference = dataset.scans.front().reference->to_isometry().inverse() *
                             dataset.scans.back().reference->to_isometry();
  return capture;
}

void run(Capture capture, bool estimate_mount, const std::optional<fs::path>& maps, bool first) {
  SensorMount mount(estimate_mount ? std::nullopt : std::optional(Eigen::Isometry3d::Identity()),
                    capture.name);
  GraphLocalizerOptions options;
  // STRATA_BENCH_SOURCE_POINTS=<n>: the registration's source point budget (0: none).
  if (const char* budget = std::getenv("STRATA_BENCH_SOURCE_POINTS"))
    options.scan_matching.registration.max_source_points = static_cast<std::size_t>(std::atol(budget));
  // STRATA_BENCH_FINE_VOXEL=<m>: the fine stage's source voxel.
  if (const char* v = std::getenv("STRATA_BENCH_FINE_VOXEL"))
    options.scan_matching.registration.stages.back().source_voxel_size = std::atof(v);
  GraphLocalizer localizer(options, Eigen::Isometry3d::Identity());
  // STRATA_BENCH_DESKEW=0: revolutions registered as measured, smeared by the motion.
  const bool deskewing =
      std::getenv("STRATA_BENCH_DESKEW") == nullptr || std::string(std::getenv("STRATA_BENCH_DESKEW")) != "0";
  MlsMap map;
  std::size_t full = 0, partial = 0, rejected = 0;
  std::vector<double> register_ms, map_ms, rmse_cm, register_cpu_ms, map_cpu_ms, scan_cpu_ms;
  Eigen::Isometry3d last_pose = Eigen::Isometry3d::Identity();
  for (ScanEvent& scan : capture.scans) {
    mount.apply(scan);
    std::vector<float> times;
    PointCloud points = pipeline::points_in_base(scan, 0.3, &times);
    auto start = std::chrono::steady_clock::now();
    double cpu_start = thread_cpu_ms();
    if (deskewing)
      localizer.deskew(points, times, std::nullopt, scan.stamp);
    const LocalizationUpdate update =
        localizer.add_scan(points, std::nullopt, scan.stamp, scan.sensor_to_base.translation());
    register_ms.push_back(ms_since(start));
    register_cpu_ms.push_back(thread_cpu_ms() - cpu_start);
    scan_cpu_ms.push_back(register_cpu_ms.back());
    if (update.registration) {
      rmse_cm.push_back(100.0 * update.registration->rmse);
      if (std::getenv("STRATA_BENCH_TRACE") != nullptr)
        std::fprintf(
            stderr, "%s t=%.2f %s rmse %.3f it %d pairs %zu/%zu x %.2f y %.2f\n", capture.name.c_str(),
            scan.stamp,
            (std::string(to_string(update.correction)) + "/" + update.registration->assessment.message)
                .c_str(),
            update.registration->rmse, update.registration->iterations, update.registration->pairs,
            update.registration->source_points, update.pose.translation().x(), update.pose.translation().y());
    }
    localizer.close_loops();  // the server's own thread; not timed
    full += update.correction == Correction::kFull ? 1 : 0;
    partial += update.correction == Correction::kPartial ? 1 : 0;
    const bool registered = !update.registration || update.correction != Correction::kNone;
    rejected += registered ? 0 : 1;
    last_pose = update.pose;
    if (!registered)
      continue;
    start = std::chrono::steady_clock::now();
    cpu_start = thread_cpu_ms();
    map.insert_scan(transformed(points, update.pose), update.pose * scan.sensor_to_base.translation(),
                    update.pose.translation());
    map_ms.push_back(ms_since(start));
    map_cpu_ms.push_back(thread_cpu_ms() - cpu_start);
    scan_cpu_ms.back() += map_cpu_ms.back();
  }
  const Eigen::Vector3d mount_position = mount.mount().value_or(Eigen::Isometry3d::Identity()).translation();
  std::printf(
      "%s  {\"capture\": \"%s\", \"scans\": %zu, \"first_scan_points\": %zu, \"registered_full\": %zu, "
      "\"registered_partly\": %zu, \"rejected\": %zu, \"mount_estimated\": %s, \"mount_height_m\": %.3f, "
      "\"register_ms\": {\"median\": %.1f, \"max\": %.1f}, \"map_ms\": {\"median\": %.1f, \"max\": %.1f}, "
      "\"per_scan_ms_median\": %.1f, \"per_scan_cpu_ms_median\": %.1f, \"rmse_cm_median\": %.2f, "
      "\"map_cells_occupied\": %zu",
      first ? "" : ",\n", capture.name.c_str(), capture.scans.size(),
      capture.scans.empty() ? 0 : capture.scans.front().points.size(), full, partial, rejected,
      mount.estimated() ? "true" : "false", mount_position.z(), median(register_ms), max_of(register_ms),
      median(map_ms), max_of(map_ms), median(register_ms) + median(map_ms),
      median(register_cpu_ms) + median(map_cpu_ms), median(rmse_cm), map.occupied_cell_count());
  if (capture.last_reference) {
    const Eigen::Isometry3d error = capture.last_reference->inverse() * last_pose;
    std::printf(", \"last_scan_from_reference_m\": %.3f, \"last_scan_from_reference_deg\": %.2f",
                error.translation().norm(), Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI);
  }
  // Each revolution's registration and mapping, CPU: where the time goes as the map fills.
  std::printf(", \"cpu_ms_per_scan\": [");
  for (std::size_t i = 0; i < scan_cpu_ms.size(); ++i)
    std::printf("%s%.1f", i == 0 ? "" : ", ", scan_cpu_ms[i]);
  std::printf("]}");
  if (maps) {
    fs::create_directories(*maps);
    save_mls_map(map, *maps / (capture.name + ".smls"));
  }
}

}  // namespace

int main(int argc, char** argv) {
  strata::app::keep_freed_memory();  // as the server does: the scan path's buffers stay mapped
  // The log (mounts found, decoder counters) to stderr: stdout is the JSON.
  spdlog::set_default_logger(spdlog::stderr_color_mt("bench"));
  fs::path data = STRATA_DATA_DIR;
  std::optional<fs::path> maps;
  int repeat = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--data")
      data = argv[i + 1];
    else if (key == "--maps")
      maps = argv[i + 1];
    else if (key == "--repeat")
      repeat = std::max(1, std::atoi(argv[i + 1]));
    else {
      std::fprintf(stderr, "usage: strata_real_capture_bench [--data DIR] [--maps DIR] [--repeat N]\n");
      return 2;
    }
  }
  const fs::path lidar = data / "lidar_pcap";
  std::vector<std::optional<Capture>> captures;
  captures.push_back(read_pcap(lidar, "hdl32_example.pcap", lidar::LidarModel::kHdl32e, "32db.yaml", false));
  // The VLP-16 captures hold one sweep each, split across the 0-degree wrap: kept as partial revolutions.
  captures.push_back(
      read_pcap(lidar, "velodyne_example.pcap", lidar::LidarModel::kVlp16, "VLP16db.yaml", true));
  captures.push_back(
      read_pcap(lidar, "velodyne_vlp16.pcap", lidar::LidarModel::kVlp16, "VLP16db.yaml", true));
  captures.push_back(
      read_pcap(lidar, "ouster_example.pcap", lidar::LidarModel::kOs1, "ouster_example.json", false));
  captures.push_back(read_3dtk(data / "3dtk_dat"));
  std::printf("[\n");
  bool first = true;
  for (auto& capture : captures) {
    if (!capture)
      continue;
    // 3DTK's scans are in the robot's frame already (slam6D's poses are of it): no mount to estimate.
    const bool estimate_mount = capture->name != "3dtk_dat";
    for (int r = 0; r < repeat; ++r) {  // each afresh: the times of one capture vary from run to run
      run(*capture, estimate_mount, maps, first);
      first = false;
    }
  }
  std::printf("\n]\n");
  if (first)
    std::fprintf(stderr, "no captures under %s (set --data)\n", data.string().c_str());
  return 0;
}

// What recording a run costs (issue 62): the simulated lidar demo (a spinning lidar driving the world's demo
// route, its IMU and odometry at the simulator's step rate) for a stretch of robot time, then every sample
// and scan written by each recording writer on this thread, as the recorder's thread does: the MCAP
// recording with zstd chunks, without, and Strata's own layout for comparison. Prints the CPU time per
// scan (the writer's work for one scan and the samples since the one before) and the megabytes per minute
// of robot time. A benchmark, not a test: it prints numbers and never fails on them.
// Usage: strata_mcap_record_bench [world] [robot seconds] [scanner: lidar|tilting]
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "drivers/replay/layout_writer.hpp"
#include "drivers/replay/mcap_recording_writer.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"

using namespace strata;
namespace fs = std::filesystem;

namespace {

constexpr double kStepRate = 100.0;  // Hz: the simulated robot's samples (SimulatedRobotConfig::step_rate)

double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

std::uintmax_t bytes_under(const fs::path& path) {
  if (fs::is_regular_file(path))
    return fs::file_size(path);
  std::uintmax_t bytes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(path)) {
    if (entry.is_regular_file())
      bytes += entry.file_size();
  }
  return bytes;
}

using Item = std::variant<RobotSample, ScanEvent>;

void measure(const char* format, const std::vector<Item>& run, std::size_t scans, double robot_seconds,
             const fs::path& where, std::unique_ptr<replay::RecordingWriter> writer) {
  const double start = thread_cpu_seconds();
  for (const Item& item : run)
    std::visit([&](const auto& value) { writer->write(value); }, item);
  writer->finish({});
  const double cpu = thread_cpu_seconds() - start;
  const double megabytes = static_cast<double>(bytes_under(where)) / 1e6;
  std::printf(
      "{\"bench\":\"mcap_record\",\"format\":\"%s\",\"scans\":%zu,\"robot_seconds\":%.1f,\"cpu_ms_per_scan\":"
      "%.3f,"
      "\"mb\":%.2f,\"mb_per_minute\":%.1f}\n",
      format, scans, robot_seconds, 1000.0 * cpu / static_cast<double>(scans), megabytes,
      megabytes * 60.0 / robot_seconds);
  fs::remove_all(where);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double robot_seconds = argc > 2 ? std::atof(argv[2]) : 30.0;
  const bool lidar = argc <= 3 || std::string(argv[3]) != "tilting";
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));
  sim::Simulator simulator(world, {.scanner = lidar ? sim::ScannerKind::kLidar : sim::ScannerKind::kTilting});
  std::vector<Item> run;
  std::size_t scans = 0, points = 0;
  for (int step = 0; step < static_cast<int>(robot_seconds * kStepRate); ++step) {
    simulator.step(1.0 / kStepRate);
    run.emplace_back(simulator.sample());
    for (ScanEvent& scan : simulator.take_scans()) {
      ++scans;
      points += scan.points.size();
      run.emplace_back(std::move(scan));
    }
  }
  std::fprintf(stderr, "%s on %s: %.0f robot seconds, %zu scans (%zu points each on average)\n",
               lidar ? "lidar" : "tilting", world_name.c_str(), robot_seconds, scans,
               points / std::max<std::size_t>(1, scans));
  const fs::path directory = fs::temp_directory_path() / ("strata-mcap-bench-" + std::to_string(::getpid()));
  fs::create_directories(directory);
  const nlohmann::json metadata{{"source", "bench"}};
  const Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  for (const auto compression : {mcap::Compression::kZstd, mcap::Compression::kNone}) {
    const fs::path file = directory / "run.mcap";
    measure(compression == mcap::Compression::kZstd ? "mcap-zstd" : "mcap-uncompressed", run, scans,
            robot_seconds, file,
            std::make_unique<replay::McapRecordingWriter>(file, metadata, start, compression));
  }
  measure("own-layout", run, scans, robot_seconds, directory / "own",
          std::make_unique<replay::LayoutWriter>(directory / "own", metadata, start));
  fs::remove_all(directory);
  return 0;
}

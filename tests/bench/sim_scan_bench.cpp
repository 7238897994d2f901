// Ray-casting speed of the simulated scanners on a built-in world: scans/s, rays/s and points/s on one
// core, from poses along the world's route. A benchmark, not a test: it prints numbers and never fails
// on them. Usage: strata_sim_scan_bench [world] [seconds per scanner]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "drivers/sim/scanners/spinning_lidar.hpp"
#include "drivers/sim/scanners/tilting_scanner.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"

using namespace strata;
using Clock = std::chrono::steady_clock;

namespace {

// Base poses along the route: drive the simulator (no scanner) and keep one pose every few seconds.
std::vector<Eigen::Isometry3d> route_poses(const std::shared_ptr<const sim::World>& world, int count) {
  sim::Simulator simulator(world, {.scanner = sim::ScannerKind::kNone});
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; static_cast<int>(poses.size()) < count && i < 200000; ++i) {
    simulator.step(0.01);
    if (i % 1500 == 0)
      poses.push_back(simulator.sample().truth->to_isometry());
  }
  return poses;
}

template <class ScanOnce>
void measure(const char* scanner, const char* world_name, double seconds, double scan_period,
             ScanOnce scan_once) {
  std::size_t scans = 0, rays = 0, points = 0;
  const auto start = Clock::now();
  double elapsed = 0.0;
  while (elapsed < seconds) {
    const ScanEvent scan = scan_once(scans);
    ++scans;
    rays += scan.rays;
    points += scan.points.size();
    elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  }
  const double per_scan_ms = 1000.0 * elapsed / static_cast<double>(scans);
  std::printf(
      "{\"bench\":\"sim_scan\",\"world\":\"%s\",\"scanner\":\"%s\",\"scans_per_s\":%.2f,\"rays_per_s\":%.0f,"
      "\"points_per_s\":%.0f,\"ms_per_scan\":%.2f,\"scan_period_ms\":%.1f,\"load\":%.4f,\"rays_per_scan\":%"
      "zu}\n",
      world_name, scanner, static_cast<double>(scans) / elapsed, static_cast<double>(rays) / elapsed,
      static_cast<double>(points) / elapsed, per_scan_ms, 1000.0 * scan_period,
      per_scan_ms / (1000.0 * scan_period), rays / scans);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double seconds = argc > 2 ? std::atof(argv[2]) : 3.0;
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));
  const auto poses = route_poses(world, 40);
  std::fprintf(stderr, "%zu poses along the %s route\n", poses.size(), world_name.c_str());

  sim::TiltingScanner tilting({}, 1);
  measure("tilting-laser", world_name.c_str(), seconds, tilting.duration(),
          [&](std::size_t k) { return tilting.scan(*world, poses[k % poses.size()]); });

  sim::SpinningLidar lidar({}, 1);
  const double period = 1.0 / lidar.config().rotation_hz;
  double t = 0.0;
  measure("vlp16", world_name.c_str(), seconds, period, [&](std::size_t k) {
    // One revolution from a pose on the route, fired in 10 ms simulation steps as the simulator does.
    const Eigen::Isometry3d& base = poses[k % poses.size()];
    while (true) {
      auto scan = lidar.advance(*world, base, t, t + 0.01);
      t += 0.01;
      if (scan)
        return std::move(*scan);
    }
  });
  return 0;
}

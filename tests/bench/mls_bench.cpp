// MLS map benchmark: insertion rate on one core (a synthetic lidar-like scan series and the real 3DTK
// scans), memory per occupied cell, and the drivable-map update for one scan's changed tiles. Prints one
// JSON object per line. Not a test: the numbers depend on the machine.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"
#include "core/mls/unseen_gaps.hpp"
#include "drivers/io/threedtk_reader.hpp"

namespace strata {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// A scan as a spinning scanner at `origin` (1.5 m above flat ground) would take it: rays on an
/// azimuth x elevation grid hitting the ground (up to 40 m) or a ring-shaped wall 30 m away, 4 m high,
/// with a few boxes in between. Ground density falls with range as in real scans.
PointCloud synthetic_scan(const Eigen::Vector3d& origin, int azimuths, int elevations) {
  PointCloud cloud;
  cloud.reserve(static_cast<std::size_t>(azimuths) * static_cast<std::size_t>(elevations));
  for (int a = 0; a < azimuths; ++a) {
    const double azimuth = 2.0 * std::numbers::pi * a / azimuths;
    for (int e = 0; e < elevations; ++e) {
      const double elevation = (-70.0 + 80.0 * e / elevations) * std::numbers::pi / 180.0;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      double t = std::numeric_limits<double>::infinity();
      if (d.z() < 0)
        t = -origin.z() / d.z();
      // Ring wall of radius 30 around the world origin: |o + t d|_xy = 30.
      const Eigen::Vector2d o2 = origin.head<2>();
      const Eigen::Vector2d d2 = d.head<2>();
      const double qa = d2.squaredNorm();
      const double qb = 2 * o2.dot(d2);
      const double qc = o2.squaredNorm() - 900.0;
      const double disc = qb * qb - 4 * qa * qc;
      if (disc >= 0 && qa > 1e-12) {
        const double tw = (-qb + std::sqrt(disc)) / (2 * qa);
        if (tw > 0 && tw < t && origin.z() + tw * d.z() < 4.0)
          t = tw;
      }
      // Pillars: vertical planes x = 10 for |y| < 1, y = 8 for |x - 3| < 1.
      if (std::abs(d.x()) > 1e-9) {
        const double tp = (10.0 - origin.x()) / d.x();
        const Eigen::Vector3d p = origin + tp * d;
        if (tp > 0 && tp < t && std::abs(p.y()) < 1.0 && p.z() < 3.0)
          t = tp;
      }
      if (std::abs(d.y()) > 1e-9) {
        const double tp = (8.0 - origin.y()) / d.y();
        const Eigen::Vector3d p = origin + tp * d;
        if (tp > 0 && tp < t && std::abs(p.x() - 3.0) < 1.0 && p.z() < 3.0)
          t = tp;
      }
      if (t < 40.0)
        cloud.push_back(origin + t * d);
    }
  }
  return cloud;
}

void bench_synthetic(int stride) {
  MlsConfig config;
  config.free_space_ray_stride = stride;
  std::vector<PointCloud> scans;
  std::vector<Eigen::Vector3d> origins;
  for (int i = 0; i < 5; ++i) {
    origins.emplace_back(2.0 * i, 0.3 * i, 1.5);
    scans.push_back(synthetic_scan(origins.back(), 2000, 1000));
  }
  MlsMap map(config);
  std::size_t points = 0;
  std::size_t cells_by_rays = 0;
  double insert_seconds = 0;
  double last_scan_seconds = 0;
  for (std::size_t i = 0; i + 1 < scans.size(); ++i) {
    const auto start = Clock::now();
    cells_by_rays += map.insert_scan(scans[i], origins[i]).cells_visited_by_rays;
    insert_seconds += seconds_since(start);
    points += scans[i].size();
  }
  const std::uint64_t before = map.version();
  const auto start = Clock::now();
  cells_by_rays += map.insert_scan(scans.back(), origins.back()).cells_visited_by_rays;
  last_scan_seconds = seconds_since(start);
  insert_seconds += last_scan_seconds;
  points += scans.back().size();

  // The drivable map for the last scan's changed tiles, from the robot's position.
  const Eigen::Vector3d ground(origins.back().x(), origins.back().y(), 0.0);
  const auto drivable_start = Clock::now();
  const CellRegion region = changed_region(map, before, ground);
  const DrivableMap drivable = compute_drivable_map(map, TraversabilityConfig{}, ground, region);
  const double drivable_ms = 1000.0 * seconds_since(drivable_start);
  const auto grid_start = Clock::now();
  const SurfaceGrid surfaces(map, region, TraversabilityConfig{});
  const double surface_grid_ms = 1000.0 * seconds_since(grid_start);
  const auto gaps_start = Clock::now();
  const SurfaceGrid with_gaps = fill_unseen_gaps(surfaces, map.resolution(), TraversabilityConfig{});
  const double gap_fill_ms = 1000.0 * seconds_since(gaps_start);

  std::printf(
      "{\"bench\":\"mls_insert_synthetic\",\"ray_stride\":%d,\"scans\":%zu,\"points\":%zu,\"points_per_s\":%."
      "0f,"
      "\"ms_per_scan\":%.1f,\"ray_cells_visited\":%zu,\"occupied_cells\":%zu,\"patches\":%zu,\"tiles\":%zu,"
      "\"bytes_per_occupied_cell\":%.1f}\n",
      stride, scans.size(), points, static_cast<double>(points) / insert_seconds, 1000.0 * last_scan_seconds,
      cells_by_rays, map.occupied_cell_count(), map.patch_count(), map.tile_count(),
      static_cast<double>(map.memory_bytes()) / static_cast<double>(map.occupied_cell_count()));
  std::printf(
      "{\"bench\":\"mls_drivable_update\",\"ray_stride\":%d,\"region_cells\":%d,\"changed_tiles\":%zu,"
      "\"free_cells\":%zu,\"start_found\":%s,\"ms\":%.2f,\"of_which_surface_grid_ms\":%.2f,"
      "\"of_which_gap_fill_ms\":%.2f,\"inferred_surfaces\":%zu}\n",
      stride, region.width * region.height, map.tiles_changed_since(before).size(), drivable.free_cells,
      drivable.start_found ? "true" : "false", drivable_ms, surface_grid_ms, gap_fill_ms,
      with_gaps.surface_count() - surfaces.surface_count());
}

void bench_3dtk(int stride) {
  const std::filesystem::path dir = std::filesystem::path(STRATA_DATA_DIR) / "3dtk_dat";
  if (!std::filesystem::exists(dir / "scan000.3d")) {
    std::fprintf(stderr, "no 3DTK scans in %s: skipping the real-data bench\n", dir.c_str());
    return;
  }
  std::vector<PointCloud> scans;
  std::vector<Eigen::Vector3d> origins;
  for (int i = 0; i < 3; ++i) {
    const std::string name = "scan00" + std::to_string(i);
    const Eigen::Isometry3d pose = io::read_3dtk_frames(dir / "reference_slam6d_2009" / (name + ".frames"));
    scans.push_back(transformed(io::read_3dtk_scan(dir / (name + ".3d")).points, pose));
    origins.push_back(pose.translation());
  }
  MlsConfig config;
  config.free_space_ray_stride = stride;
  double best = std::numeric_limits<double>::infinity();
  std::size_t points = 0;
  std::size_t occupied = 0;
  double bytes_per_cell = 0;
  for (int repeat = 0; repeat < 5; ++repeat) {
    MlsMap map(config);
    points = 0;
    const auto start = Clock::now();
    for (std::size_t i = 0; i < scans.size(); ++i) {
      map.insert_scan(scans[i], origins[i]);
      points += scans[i].size();
    }
    best = std::min(best, seconds_since(start));
    occupied = map.occupied_cell_count();
    bytes_per_cell = static_cast<double>(map.memory_bytes()) / static_cast<double>(occupied);
  }
  std::printf(
      "{\"bench\":\"mls_insert_3dtk\",\"ray_stride\":%d,\"scans\":3,\"points\":%zu,\"points_per_s\":%.0f,"
      "\"occupied_cells\":%zu,\"bytes_per_occupied_cell\":%.1f}\n",
      stride, points, static_cast<double>(points) / best, occupied, bytes_per_cell);
}

}  // namespace
}  // namespace strata

int main() {
  for (const int stride : {0, 8, 32}) {
    strata::bench_synthetic(stride);
    strata::bench_3dtk(stride);
  }
}

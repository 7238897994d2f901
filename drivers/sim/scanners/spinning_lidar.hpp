#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "drivers/scan_event.hpp"
#include "drivers/sim/scanners/beam_model.hpp"

namespace strata::sim {

/// A spinning multi-beam lidar (Velodyne VLP-16-like): `beams` lasers fanned between the elevation
/// limits, turning at `rotation_hz`, firing every `azimuth_step_deg`. It scans while the robot drives,
/// so each firing sees the world from where the robot is at that instant, as on a real sensor.
struct SpinningLidarConfig {
  int beams = 16;
  double elevation_min_deg = -15.0;
  double elevation_max_deg = 15.0;
  double azimuth_step_deg = 0.2;
  double rotation_hz = 10.0;
  BeamModel beam{.min_range = 0.4, .max_range = 100.0, .range_stddev = 0.02, .no_return = NoReturn::kDrop};
  Eigen::Vector3d mount{0.0, 0.0, 1.4};  ///< sensor position on the base (base frame, m)
};

class SpinningLidar {
 public:
  SpinningLidar(SpinningLidarConfig config, std::uint64_t seed);

  /// Fires every laser due in the simulated interval [t0, t1) from the base pose `base_in_world`.
  /// Returns the revolution that this interval completed, if one did (points in the sensor frame).
  std::optional<ScanEvent> advance(const World& world, const Eigen::Isometry3d& base_in_world, double t0,
                                   double t1);
  [[nodiscard]] std::size_t rays_per_revolution() const;
  [[nodiscard]] const SpinningLidarConfig& config() const { return config_; }

 private:
  void fire(const World& world, const Eigen::Isometry3d& sensor, int column, float time);

  SpinningLidarConfig config_;
  std::mt19937_64 rng_;
  int columns_;                       // firings per revolution
  std::vector<Eigen::Vector3d> fan_;  // beam directions at azimuth 0
  long long next_column_ = -1;        // counts firings since time 0; -1 until the first advance
  ScanEvent current_;
};

}  // namespace strata::sim

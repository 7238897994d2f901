#pragma once

#include <cstdint>
#include <optional>
#include <random>

#include "drivers/scan_event.hpp"
#include "drivers/sim/scanners/beam_model.hpp"

namespace strata::sim {

/// The thesis robot's 3D scanner (section 3.1): a 2D laser (SICK LMS200-like) whose vertical slice
/// spans `slice_fov_deg` from straight down to straight up, turned about the vertical axis by an
/// actuator through `rotation_deg`. The robot stands still while it scans (stop-and-go).
struct TiltingScannerConfig {
  double slice_fov_deg = 180.0;
  double slice_step_deg = 1.0;
  double rotation_deg = 360.0;
  double rotation_step_deg = 1.0;
  double slices_per_second = 75.0;  ///< the LMS200's scan rate: sets how long a 3D scan takes
  BeamModel beam{.min_range = 0.1, .max_range = 8.1, .range_stddev = 0.01, .no_return = NoReturn::kMaxRange};
  Eigen::Vector3d mount{0.2, 0.0, 1.05};  ///< sensor position on the base (base frame, m)
};

class TiltingScanner {
 public:
  TiltingScanner(TiltingScannerConfig config, std::uint64_t seed);

  /// Seconds one full 3D scan takes.
  [[nodiscard]] double duration() const;
  /// Takes a whole scan at once from the base pose `base_in_world` (standing still). Fills points,
  /// sensor, duration, rays and the mounting; the caller stamps it and adds the poses.
  [[nodiscard]] ScanEvent scan(const World& world, const Eigen::Isometry3d& base_in_world);

  /// Starts a scan at simulated time `t`; `advance` then fires the slices as they come due, so the
  /// ray casting is spread over the scan's duration as on the real sensor.
  void begin(double t);
  [[nodiscard]] bool scanning() const { return next_slice_ >= 0; }
  /// Drops the scan under way (the base has to move): the next begin() starts afresh.
  void abandon() { next_slice_ = -1; }
  /// Fires the slices due in [t0, t1); returns the scan once its last slice is fired.
  std::optional<ScanEvent> advance(const World& world, const Eigen::Isometry3d& base_in_world, double t0,
                                   double t1);
  [[nodiscard]] std::size_t rays_per_scan() const;
  [[nodiscard]] const TiltingScannerConfig& config() const { return config_; }

 private:
  void fire_slice(const World& world, const Eigen::Isometry3d& sensor, int slice, ScanEvent& event);
  [[nodiscard]] ScanEvent empty_event() const;

  TiltingScannerConfig config_;
  std::mt19937_64 rng_;
  int slices_;
  int beams_per_slice_;
  int next_slice_ = -1;  // -1: not scanning
  double started_ = 0.0;
  ScanEvent current_;
};

}  // namespace strata::sim

#pragma once

#include <cstdint>
#include <optional>
#include <random>

#include "core/geometry/pose.hpp"
#include "drivers/sim/diff_drive_base.hpp"

namespace strata::sim {

/// Slip and calibration errors of wheel encoders. Defaults are of the order of a wheelchair on a floor:
/// a few millimetres of drift per metre, heading error that grows with distance.
struct OdometryNoise {
  double wheel_scale_stddev = 0.002;  ///< per-run wheel radius error (fraction), drawn once per wheel
  double slip_stddev = 0.004;         ///< random slip, m per sqrt(m) of wheel travel
};

/// Integrates noisy wheel travel into an odometry pose, as a real base's controller does.
/// The noise is drawn from a generator seeded once, so the same seed gives the same drift.
class WheelOdometry {
 public:
  WheelOdometry(double wheel_separation, OdometryNoise noise, std::uint64_t seed, Pose2 start = {});

  /// One step of `truth` wheel travel. `gyro_turn`: the turn a gyro measured meanwhile, which replaces the
  /// wheels' (gyro-aided odometry, as most bases with an IMU report it: wheels slip in turns, gyros not).
  void integrate(const WheelTravel& truth, std::optional<double> gyro_turn = std::nullopt);
  [[nodiscard]] const Pose2& pose() const { return pose_; }
  /// Total distance the wheels report, in metres (the odometer).
  [[nodiscard]] double distance() const { return distance_; }

 private:
  double measure(double travel, double scale_error);

  double wheel_separation_;
  OdometryNoise noise_;
  std::mt19937_64 rng_;
  double left_scale_error_;
  double right_scale_error_;
  Pose2 pose_;
  double distance_ = 0.0;
};

}  // namespace strata::sim

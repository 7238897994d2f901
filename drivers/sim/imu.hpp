#pragma once

#include <cstdint>
#include <random>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"

namespace strata::sim {

/// A consumer MEMS IMU on the base (an automotive-grade gyro and accelerometer of a few dollars, as in
/// most mobile robots' base controllers). The gyro's yaw rate replaces the wheels' turn in the odometry
/// (the wheels' turn is what slips and drifts); the accelerometer reports which way is up with each scan.
struct ImuNoise {
  /// Gyro bias left after the base's calibration at start, rad/s (stddev; drawn once per run): 10 deg/h.
  double gyro_bias_stddev = 5e-5;
  /// Gyro angle random walk, rad/sqrt(s): 0.01 deg/s/sqrt(Hz).
  double gyro_noise_density = 1.7e-4;
  /// The accelerometer's mounting and calibration error, rad (stddev per axis; drawn once per run).
  double tilt_bias_stddev = 0.002;
  /// Tilt noise of one reading, rad: averaged over a scan standing still, and while the base drives
  /// (its accelerations, which the accelerometer cannot tell from gravity).
  double tilt_noise_standing = 0.002;
  double tilt_noise_moving = 0.01;
};

/// The simulated IMU: turns and tilts measured from the truth with ImuNoise's errors, from a generator
/// seeded once, so the same seed gives the same readings.
class SimulatedImu {
 public:
  SimulatedImu(ImuNoise noise, std::uint64_t seed);

  /// The gyro's measure of a turn about the base's vertical axis that took `dt` seconds.
  [[nodiscard]] double measure_turn(double true_turn, double dt);
  /// The gyro's measure of the turn while the base stood `dt` seconds: its bias and noise. From a
  /// sequence of its own, so reading it leaves the turns and the gravity readings as they were.
  [[nodiscard]] double measure_standing_turn(double dt);
  /// The gyro's noise density, rad/sqrt(s): what a driver knows from the datasheet.
  [[nodiscard]] double gyro_noise_density() const { return noise_.gyro_noise_density; }
  /// Which way is up in the base frame of `truth`, as the accelerometer reads it with a scan.
  [[nodiscard]] GravityReading measure_gravity(const Pose3& truth, bool standing);
  /// The same accelerometer as the base controller streams it with every sample (same bias). Its noise
  /// comes from a sequence of its own, so streaming it leaves the readings with the scans as they were.
  [[nodiscard]] GravityReading stream_gravity(const Pose3& truth, bool standing);
  /// The accelerometer's mounting error drawn for this run: a rotation vector in the base frame (radians;
  /// z 0) that takes the true up to where it reads it, noise aside. What a localizer should find.
  [[nodiscard]] Eigen::Vector3d mounting_error() const { return {tilt_bias_.x(), tilt_bias_.y(), 0.0}; }
  /// The gyro's bias drawn for this run, rad/s: the heading drift a localizer should find (with the
  /// opposite sign: HeadingDrift's is what to add).
  [[nodiscard]] double gyro_bias() const { return gyro_bias_; }

 private:
  [[nodiscard]] GravityReading read_gravity(const Pose3& truth, bool standing, std::mt19937_64& rng) const;

  ImuNoise noise_;
  std::mt19937_64 rng_;
  std::mt19937_64 stream_rng_;
  std::mt19937_64 standing_rng_;
  double gyro_bias_ = 0.0;
  Eigen::Vector2d tilt_bias_ = Eigen::Vector2d::Zero();  ///< about the base's x and y axes, rad
};

}  // namespace strata::sim

#include "drivers/sim/imu.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace strata::sim {

namespace {

double draw(std::mt19937_64& rng, double stddev) {
  return stddev > 0.0 ? std::normal_distribution<double>(0.0, stddev)(rng) : 0.0;
}

}  // namespace

SimulatedImu::SimulatedImu(ImuNoise noise, std::uint64_t seed)
    : noise_(noise),
      rng_(seed ^ 0x1f3d5b79a4c6e821ULL),  // not the wheels' sequence
      stream_rng_(seed ^ 0x6a09e667f3bcc908ULL),
      standing_rng_(seed ^ 0xbb67ae8584caa73bULL) {
  gyro_bias_ = draw(rng_, noise_.gyro_bias_stddev);
  tilt_bias_ = {draw(rng_, noise_.tilt_bias_stddev), draw(rng_, noise_.tilt_bias_stddev)};
}

double SimulatedImu::measure_turn(double true_turn, double dt) {
  if (dt <= 0.0)
    return true_turn;
  // Bias integrates linearly, white rate noise as a random walk in the angle.
  return true_turn + gyro_bias_ * dt + draw(rng_, noise_.gyro_noise_density * std::sqrt(dt));
}

double SimulatedImu::measure_standing_turn(double dt) {
  if (dt <= 0.0)
    return 0.0;
  return gyro_bias_ * dt + draw(standing_rng_, noise_.gyro_noise_density * std::sqrt(dt));
}

GravityReading SimulatedImu::measure_gravity(const Pose3& truth, bool standing) {
  return read_gravity(truth, standing, rng_);
}

GravityReading SimulatedImu::stream_gravity(const Pose3& truth, bool standing) {
  return read_gravity(truth, standing, stream_rng_);
}

GravityReading SimulatedImu::read_gravity(const Pose3& truth, bool standing, std::mt19937_64& rng) const {
  const double noise = standing ? noise_.tilt_noise_standing : noise_.tilt_noise_moving;
  const Eigen::Vector3d true_up = truth.to_isometry().linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d error(tilt_bias_.x() + draw(rng, noise), tilt_bias_.y() + draw(rng, noise), 0.0);
  const double angle = error.norm();
  GravityReading reading;
  reading.up_in_base = true_up;
  if (angle > 0.0)
    reading.up_in_base = (Eigen::AngleAxisd(angle, error / angle) * true_up).normalized();
  // What the driver says of it: the noise and the bias together.
  reading.sigma = std::hypot(noise, noise_.tilt_bias_stddev);
  return reading;
}

}  // namespace strata::sim

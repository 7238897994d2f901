#include "drivers/sim/wheel_odometry.hpp"

#include <cmath>

namespace strata::sim {

WheelOdometry::WheelOdometry(double wheel_separation, OdometryNoise noise, std::uint64_t seed, Pose2 start)
    : wheel_separation_(wheel_separation), noise_(noise), rng_(seed), pose_(start) {
  std::normal_distribution<double> scale(0.0, noise_.wheel_scale_stddev);
  left_scale_error_ = noise_.wheel_scale_stddev > 0.0 ? scale(rng_) : 0.0;
  right_scale_error_ = noise_.wheel_scale_stddev > 0.0 ? scale(rng_) : 0.0;
}

double WheelOdometry::measure(double travel, double scale_error) {
  double measured = travel * (1.0 + scale_error);
  if (noise_.slip_stddev > 0.0 && travel != 0.0) {
    // Slip accumulates like a random walk in the distance rolled: stddev grows with sqrt(travel).
    std::normal_distribution<double> slip(0.0, noise_.slip_stddev * std::sqrt(std::abs(travel)));
    measured += slip(rng_);
  }
  return measured;
}

void WheelOdometry::integrate(const WheelTravel& truth, std::optional<double> gyro_turn) {
  const double left = measure(truth.left, left_scale_error_);
  const double right = measure(truth.right, right_scale_error_);
  const double distance = 0.5 * (left + right);
  const double turn = gyro_turn.value_or((right - left) / wheel_separation_);
  // Midpoint integration: accurate to second order for the short steps of an encoder loop.
  const Pose2 delta{distance * std::cos(0.5 * turn), distance * std::sin(0.5 * turn), turn};
  pose_ = pose_.compose(delta);
  distance_ += std::abs(distance);
}

}  // namespace strata::sim

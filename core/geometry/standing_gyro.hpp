#pragma once

#include <cmath>

namespace strata {

/// What the base's gyro read about its vertical axis while the base stood still: its bias, which is what
/// turns the odometry's heading while the base moves (the Earth's turn included). A stop-and-go base
/// stands for every scan, so drivers with a gyro report it with the scan.
struct StandingGyro {
  double rate = 0.0;     ///< rad/s, the mean over the stand
  double seconds = 0.0;  ///< how long the base stood
  /// The mean's standard deviation, rad/s: the gyro's noise density over the square root of `seconds`.
  double sigma = 0.0;

  /// A finite rate over some time, with a sigma to weigh it by.
  [[nodiscard]] bool usable() const {
    return std::isfinite(rate) && std::isfinite(seconds) && std::isfinite(sigma) && seconds > 0.0 &&
           sigma > 0.0;
  }
};

}  // namespace strata

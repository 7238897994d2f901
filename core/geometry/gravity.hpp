#pragma once

#include <Eigen/Core>

namespace strata {

/// Which way is up, as an accelerometer or inclinometer on the base measured it while a scan was taken:
/// roll and pitch without drift (a heading it cannot give). Drivers with an IMU report it with the scan.
struct GravityReading {
  Eigen::Vector3d up_in_base = Eigen::Vector3d::UnitZ();  ///< unit vector, base frame
  /// Standard deviation of the tilt it gives, radians: small standing still, larger while the base
  /// accelerates (the accelerometer cannot tell the two apart).
  double sigma = 0.01;
};

}  // namespace strata

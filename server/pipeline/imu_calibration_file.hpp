#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>

namespace strata::pipeline {

/// What a run learnt of the base's IMU that holds for the next run of the same robot: how its
/// accelerometer is mounted. The scan path learns it only as the robot turns, and until then tilts the
/// way by it: over ten campus runs the height was 0.12 m off on average, 0.08 m when each started from
/// what its first run kept (docs/benchmarks.md, "IMU calibration kept between runs"). The gyro's bias is
/// not kept: it changes with every start and with the temperature.
struct ImuCalibration {
  std::string imu;  ///< which IMU it is (RobotDriver::imu_name)
  /// The accelerometer's mounting error about the base's x and y axes (roll, pitch), radians: what
  /// GraphLocalizer::start_from_calibration takes.
  Eigen::Vector2d mounting = Eigen::Vector2d::Zero();
  std::size_t loops = 0;      ///< loop closures in the pose graph that estimated it
  std::size_t keyframes = 0;  ///< keyframes in that graph
};

/// The calibration file: one IMU's calibration as JSON (docs/architecture.md 4.1). Throws
/// std::runtime_error naming the file and what is wrong with it when it is no such file.
[[nodiscard]] ImuCalibration parse_imu_calibration(const std::string& text);
[[nodiscard]] std::string format_imu_calibration(const ImuCalibration& calibration);

}  // namespace strata::pipeline

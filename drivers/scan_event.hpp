#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"
#include "core/geometry/standing_gyro.hpp"

namespace strata {

/// One full 3D scan as a driver hands it to the pipeline (docs/architecture.md 3).
struct ScanEvent {
  double stamp = 0.0;                   ///< seconds; when the scan completed
  double duration = 0.0;                ///< seconds the scan took to take
  std::string sensor;                   ///< which sensor, e.g. "tilting-laser", "vlp16"
  std::vector<Eigen::Vector3f> points;  ///< in the sensor frame, as measured (no motion compensation)
  /// Per point, when it was measured: seconds relative to `stamp` (<= 0). Empty when the sensor does not
  /// say (a tilting scanner; a recording without times): its points are then not deskewed.
  std::vector<float> point_times;
  Eigen::Isometry3d sensor_to_base = Eigen::Isometry3d::Identity();  ///< the sensor's mounting
  Pose3 odometry;                                                    ///< the base's odometry pose at `stamp`
  /// False for a base without odometry (a lidar alone): `odometry` is then a constant, and the localizer
  /// predicts the motion from the last scans instead (ConstantVelocityPrediction).
  bool has_odometry = true;
  std::optional<Pose3> truth;  ///< the base's true pose at `stamp`, when simulated
  /// Which way was up while the scan was taken, from the base's IMU: none without one.
  std::optional<GravityReading> gravity;
  /// What the base's gyro read while the base stood since the last scan (a stop-and-go scanner's stand
  /// for this one): none without a gyro, or where the base did not stand.
  std::optional<StandingGyro> standing_gyro;
  std::size_t rays = 0;    ///< beams fired, returns or not
  double max_range = 0.0;  ///< m; readings at this range mean "no return" (0: the sensor reports none)
  /// Wall-clock time (s since the Unix epoch) the pipeline received it: what scan-to-client latency is
  /// measured from. 0 until the pipeline sets it.
  double received_at = 0.0;
};

}  // namespace strata

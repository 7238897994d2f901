#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <numbers>

namespace strata {

/// What the pose graph has done, for status and benchmarks.
struct PoseGraphStatus {
  std::size_t keyframes = 0;
  std::size_t loops = 0;          ///< loop edges in the graph
  std::size_t loops_dropped = 0;  ///< found, then dropped as false by the optimizer
  std::size_t optimizations = 0;  ///< after loops closed
  /// Before the first loop: optimizations whose heights the keyframes and the scan path took
  /// (GraphLocalizerOptions::height_before_loops).
  std::size_t height_optimizations = 0;
  /// Keyframes of an earlier pass that joined the scan path's local map (GraphLocalizerOptions::
  /// earlier_pass_radius), each time one did.
  std::size_t earlier_pass_joins = 0;
  double last_loop_stamp = -1.0;  ///< scan time of the newest keyframe of the last loop closure; -1: none
  double last_correction = 0.0;   ///< metres the last loop closure moved the newest keyframe
  double last_optimization_seconds = 0.0;
  /// The odometry's heading drift last fitted (before the first loop, or after the last optimization),
  /// rad per second of motion, taken out of its turns (fit_heading_drift); 0 until there is one.
  double heading_drift = 0.0;
  /// The gravity reading's mounting error as the last optimization estimated it: a rotation vector in the
  /// base frame, radians (x roll, y pitch; z 0). Zero until then.
  Eigen::Vector3d gravity_mounting = Eigen::Vector3d::Zero();

  /// The same in degrees an hour, as status and logs report it (a gyro's datasheet unit).
  [[nodiscard]] double heading_drift_deg_per_h() const {
    return heading_drift * 180.0 / std::numbers::pi * 3600.0;
  }
  /// The mounting error's roll and pitch in degrees, as status and logs report it.
  [[nodiscard]] Eigen::Vector2d gravity_mounting_deg() const {
    return gravity_mounting.head<2>() * 180.0 / std::numbers::pi;
  }
};

}  // namespace strata

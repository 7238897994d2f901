#pragma once

#include <Eigen/Geometry>
#include <span>
#include <vector>

#include "core/points/point_cloud.hpp"

namespace strata {

/// Which of a scan's readings measure the world (as KISS-ICP's Preprocessor keeps a band of ranges).
struct ScanCleaning {
  double min_range = 0.3;        ///< m; nearer returns are the robot itself
  double no_return_range = 0.0;  ///< m; readings at this range mean "no return" (0: the sensor reports none)
};

/// The measurements among `points` (the sensor's frame), moved into the base frame by `sensor_to_base`: no
/// NaN or infinite point, none nearer than min_range, no "no return" (noise pushes real returns just under
/// that range, so the last centimetre below it counts as one too). `times`: each point's time (empty or
/// not one per point: unknown); `kept_times`, when given, gets the kept points' times, or nothing when
/// they are unknown.
[[nodiscard]] PointCloud clean_scan(std::span<const Eigen::Vector3f> points,
                                    const Eigen::Isometry3d& sensor_to_base, const ScanCleaning& cleaning,
                                    std::span<const float> times = {},
                                    std::vector<float>* kept_times = nullptr);

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace strata::bench {

/// One scan's pose as estimated and as the reference has it, in the same frame.
struct TrackedPose {
  double stamp = 0.0;
  Eigen::Isometry3d estimate = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d reference = Eigen::Isometry3d::Identity();
};

/// How far an estimated trajectory is from its reference.
struct TrajectoryErrors {
  double max_horizontal_m = 0.0;  ///< absolute: the largest distance in the ground plane
  double max_3d_m = 0.0;
  double final_horizontal_m = 0.0;
  double max_heading_deg = 0.0;
  double path_m = 0.0;  ///< the reference's length
  /// Relative: each stretch of 10 m of the reference from every scan on, the translation error of the
  /// estimated motion over it (m per 10 m); -1 when the path is shorter.
  double relative_per_10m_mean_m = -1.0;
  double relative_per_10m_max_m = -1.0;
  /// KITTI's drift: the mean of translation error / length over every stretch of each length, in %. KITTI
  /// uses 100-800 m; these sequences are 10-25 m long, so 2, 4, 6, 8 and 10 m; -1 when none fits.
  double drift_percent = -1.0;
};

[[nodiscard]] TrajectoryErrors trajectory_errors(const std::vector<TrackedPose>& track);

}  // namespace strata::bench

#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <optional>
#include <span>

#include "drivers/lidar/decoded_packet.hpp"

namespace strata::lidar {

/// The sensor's pose in a fixed frame (odometry's) at a time; nullopt where it is not known.
using SensorPoseAt = std::function<std::optional<Eigen::Isometry3d>(double time)>;

/// Undoes the sensor's motion during a revolution: re-expresses every point, measured at its own time,
/// in the sensor frame at `reference_time` (the scan's end stamp). The pose is sampled at `samples`
/// times over the points' span and interpolated between them (a few dozen look-ups instead of one per
/// point). Returns false and leaves the points as they are when a needed pose is unknown.
bool compensate_motion(std::span<LidarPoint> points, double reference_time, const SensorPoseAt& pose_at,
                       std::size_t samples = 64);

/// Timestamped poses (e.g. wheel odometry) with interpolation: linear in translation, slerp in rotation.
/// Times outside the first..last pose give nullopt (no extrapolation).
class PoseHistory {
 public:
  void add(double time, const Eigen::Isometry3d& pose) { poses_[time] = pose; }
  /// Forgets poses older than `time`, keeping one at or before it for interpolation.
  void drop_before(double time);
  [[nodiscard]] std::optional<Eigen::Isometry3d> at(double time) const;
  [[nodiscard]] std::size_t size() const { return poses_.size(); }

 private:
  std::map<double, Eigen::Isometry3d> poses_;
};

/// Interpolates between two rigid transforms, `fraction` 0 giving `a` and 1 giving `b`.
[[nodiscard]] Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                            double fraction);

}  // namespace strata::lidar

#include "drivers/lidar/motion_compensation.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace strata::lidar {

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction) {
  const Eigen::Quaterniond qa(a.rotation());
  const Eigen::Quaterniond qb(b.rotation());
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = qa.slerp(fraction, qb).toRotationMatrix();
  result.translation() = a.translation() + fraction * (b.translation() - a.translation());
  return result;
}

bool compensate_motion(std::span<LidarPoint> points, double reference_time, const SensorPoseAt& pose_at,
                       std::size_t samples) {
  if (points.empty())
    return true;
  samples = std::max<std::size_t>(samples, 2);
  const auto [earliest, latest] = std::minmax_element(
      points.begin(), points.end(), [](const LidarPoint& a, const LidarPoint& b) { return a.time < b.time; });
  const double first = earliest->time;
  const double span = latest->time - first;
  const std::optional<Eigen::Isometry3d> reference = pose_at(reference_time);
  if (!reference)
    return false;
  const Eigen::Isometry3d to_reference = reference->inverse();
  // Sensor-at-sample to sensor-at-reference, for each sample time.
  std::vector<Eigen::Isometry3d> corrections;
  corrections.reserve(samples);
  for (std::size_t k = 0; k < samples; ++k) {
    const double time = first + span * static_cast<double>(k) / static_cast<double>(samples - 1);
    const std::optional<Eigen::Isometry3d> pose = pose_at(time);
    if (!pose)
      return false;
    corrections.push_back(to_reference * *pose);
  }
  for (LidarPoint& point : points) {
    const double position = span > 0.0 ? (point.time - first) / span * static_cast<double>(samples - 1) : 0.0;
    const auto index = std::min(static_cast<std::size_t>(std::max(position, 0.0)), samples - 2);
    const Eigen::Isometry3d correction =
        interpolate(corrections[index], corrections[index + 1], position - static_cast<double>(index));
    point.position = (correction * point.position.cast<double>()).cast<float>();
  }
  return true;
}

void PoseHistory::drop_before(double time) {
  auto keep = poses_.upper_bound(time);
  if (keep != poses_.begin())
    --keep;
  poses_.erase(poses_.begin(), keep);
}

std::optional<Eigen::Isometry3d> PoseHistory::at(double time) const {
  if (poses_.empty())
    return std::nullopt;
  const auto after = poses_.lower_bound(time);
  if (after == poses_.end())
    return std::nullopt;
  if (after->first == time)
    return after->second;
  if (after == poses_.begin())
    return std::nullopt;
  const auto before = std::prev(after);
  const double fraction = (time - before->first) / (after->first - before->first);
  return interpolate(before->second, after->second, fraction);
}

}  // namespace strata::lidar

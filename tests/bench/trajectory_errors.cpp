#include "bench/trajectory_errors.hpp"

#include <algorithm>
#include <cmath>

#include "core/geometry/pose.hpp"

namespace strata::bench {
namespace {

/// The first scan at least `length` metres of reference path after scan `from`; none past the end.
std::size_t stretch_end(const std::vector<double>& distance, std::size_t from, double length) {
  const auto it = std::lower_bound(distance.begin() + static_cast<std::ptrdiff_t>(from), distance.end(),
                                   distance[from] + length);
  return static_cast<std::size_t>(it - distance.begin());
}

/// The translation error of the estimated motion from scan i to scan j against the reference's.
double motion_error(const std::vector<TrackedPose>& track, std::size_t i, std::size_t j) {
  const Eigen::Isometry3d reference = track[i].reference.inverse() * track[j].reference;
  const Eigen::Isometry3d estimate = track[i].estimate.inverse() * track[j].estimate;
  return (reference.inverse() * estimate).translation().norm();
}

}  // namespace

TrajectoryErrors trajectory_errors(const std::vector<TrackedPose>& track) {
  TrajectoryErrors errors;
  if (track.empty())
    return errors;
  std::vector<double> distance{0.0};  // along the reference, at each scan
  for (std::size_t i = 0; i < track.size(); ++i) {
    const Eigen::Vector3d offset = track[i].estimate.translation() - track[i].reference.translation();
    errors.max_horizontal_m = std::max(errors.max_horizontal_m, offset.head<2>().norm());
    errors.max_3d_m = std::max(errors.max_3d_m, offset.norm());
    double heading = heading_of(track[i].estimate) - heading_of(track[i].reference);
    heading = std::remainder(heading, 2.0 * M_PI);
    errors.max_heading_deg = std::max(errors.max_heading_deg, std::abs(heading) * 180.0 / M_PI);
    if (i > 0)
      distance.push_back(distance.back() +
                         (track[i].reference.translation() - track[i - 1].reference.translation()).norm());
  }
  errors.final_horizontal_m =
      (track.back().estimate.translation() - track.back().reference.translation()).head<2>().norm();
  errors.path_m = distance.back();

  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < track.size(); ++i) {
    const std::size_t j = stretch_end(distance, i, 10.0);
    if (j >= track.size())
      break;
    const double error = motion_error(track, i, j) * 10.0 / (distance[j] - distance[i]);
    sum += error;
    ++count;
    errors.relative_per_10m_max_m = std::max(errors.relative_per_10m_max_m, error);
  }
  if (count > 0)
    errors.relative_per_10m_mean_m = sum / static_cast<double>(count);

  double drift = 0.0;
  std::size_t stretches = 0;
  for (const double length : {2.0, 4.0, 6.0, 8.0, 10.0}) {
    for (std::size_t i = 0; i < track.size(); ++i) {
      const std::size_t j = stretch_end(distance, i, length);
      if (j >= track.size())
        break;
      drift += motion_error(track, i, j) / (distance[j] - distance[i]);
      ++stretches;
    }
  }
  if (stretches > 0)
    errors.drift_percent = 100.0 * drift / static_cast<double>(stretches);
  return errors;
}

}  // namespace strata::bench

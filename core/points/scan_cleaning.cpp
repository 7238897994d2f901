#include "core/points/scan_cleaning.hpp"

#include <limits>

namespace strata {

PointCloud clean_scan(std::span<const Eigen::Vector3f> points, const Eigen::Isometry3d& sensor_to_base,
                      const ScanCleaning& cleaning, std::span<const float> times,
                      std::vector<float>* kept_times) {
  const double max_range = cleaning.no_return_range > 0.0 ? cleaning.no_return_range - 0.01
                                                          : std::numeric_limits<double>::infinity();
  const bool timed = kept_times != nullptr && times.size() == points.size();
  if (kept_times != nullptr) {
    kept_times->clear();
    if (timed)
      kept_times->reserve(points.size());
  }
  PointCloud cleaned;
  cleaned.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!p.allFinite())
      continue;
    const double range = static_cast<double>(p.norm());
    if (range < cleaning.min_range || range > max_range)
      continue;
    cleaned.push_back(sensor_to_base * p.cast<double>());
    if (timed)
      kept_times->push_back(times[i]);
  }
  return cleaned;
}

}  // namespace strata

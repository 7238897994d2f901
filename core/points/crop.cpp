#include "core/points/crop.hpp"

namespace strata {

PointCloud crop_range(const PointCloud& points, double min_range, double max_range) {
  const double min_squared = min_range * min_range;
  const double max_squared = max_range * max_range;
  PointCloud kept;
  kept.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    const double squared = p.squaredNorm();
    if (squared >= min_squared && squared <= max_squared)
      kept.push_back(p);
  }
  return kept;
}

}  // namespace strata

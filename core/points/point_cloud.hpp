#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace strata {

/// A 3D point cloud in metres, in the frame of whatever produced it. A plain vector: cheap to build,
/// iterate and pass to the search structures, with nothing to keep in sync.
using PointCloud = std::vector<Eigen::Vector3d>;

/// `points` mapped through `transform` (p' = R p + t).
[[nodiscard]] inline PointCloud transformed(const PointCloud& points, const Eigen::Isometry3d& transform) {
  PointCloud out;
  out.reserve(points.size());
  for (const Eigen::Vector3d& p : points)
    out.push_back(transform * p);
  return out;
}

}  // namespace strata

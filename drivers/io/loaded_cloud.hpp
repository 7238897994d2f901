#pragma once

#include <cstddef>

#include "core/points/point_cloud.hpp"

namespace strata::io {

/// What a reader returns: the finite points, in metres, and how many it dropped for being NaN or infinite
/// (organised clouds mark missing returns that way).
struct LoadedCloud {
  PointCloud points;
  std::size_t dropped_non_finite = 0;
};

/// Adds a point unless a coordinate is NaN or infinite.
inline void add_finite(LoadedCloud& cloud, const Eigen::Vector3d& point) {
  if (point.allFinite())
    cloud.points.push_back(point);
  else
    ++cloud.dropped_non_finite;
}

}  // namespace strata::io

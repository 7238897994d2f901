#pragma once

#include <optional>

#include "core/ann/neighbor.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// The reference nearest-neighbour search: compares the query with every point. O(N) per query; kept to
/// check the real search structures against and to measure them by.
[[nodiscard]] inline std::optional<Neighbor> brute_force_nearest(const PointCloud& points,
                                                                 const Eigen::Vector3d& query,
                                                                 double max_distance) {
  std::optional<Neighbor> best;
  double best_squared = max_distance * max_distance;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double squared = (points[i] - query).squaredNorm();
    if (squared <= best_squared) {
      best_squared = squared;
      best = Neighbor{i, squared};
    }
  }
  return best;
}

}  // namespace strata

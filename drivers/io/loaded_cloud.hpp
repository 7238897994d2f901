#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "core/points/point_cloud.hpp"

namespace strata::io {

/// What a reader returns: the finite points, in metres, and how many it dropped for being NaN or infinite
/// (organised clouds mark missing returns that way).
struct LoadedCloud {
  PointCloud points;
  std::size_t dropped_non_finite = 0;
  /// Per point, when it was measured, where the file says (a PCD "time" field, seconds, in the file's own
  /// reference: Strata's recordings measure from the scan's stamp). Empty otherwise.
  std::vector<float> times;
};

/// Adds a point unless a coordinate is NaN or infinite; with its time, when the file has times.
inline void add_finite(LoadedCloud& cloud, const Eigen::Vector3d& point,
                       std::optional<double> time = std::nullopt) {
  if (!point.allFinite()) {
    ++cloud.dropped_non_finite;
    return;
  }
  cloud.points.push_back(point);
  if (time)
    cloud.times.push_back(static_cast<float>(*time));
}

}  // namespace strata::io

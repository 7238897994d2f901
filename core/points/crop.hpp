#pragma once

#include "core/points/point_cloud.hpp"

namespace strata {

/// Keeps points whose distance from the sensor origin lies in [min_range, max_range] (metres). Drops the
/// robot's own body (very short ranges) and max-range readings, which are no surface at all.
[[nodiscard]] PointCloud crop_range(const PointCloud& points, double min_range, double max_range);

}  // namespace strata

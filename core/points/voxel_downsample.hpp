#pragma once

#include "core/points/point_cloud.hpp"

namespace strata {

/// Keeps one point per cubic voxel of edge `voxel_size` (metres): the first point seen in each. Keeping a
/// measured point rather than the voxel's centroid avoids inventing points between two surfaces that share
/// a voxel; order is preserved. Non-positive `voxel_size` returns the cloud unchanged.
[[nodiscard]] PointCloud voxel_downsample(const PointCloud& points, double voxel_size);

/// The same over the points at least `min_range` from the origin (the sensor): the robot's own
/// returns dropped and the rest thinned in one pass over the scan.
[[nodiscard]] PointCloud voxel_downsample(const PointCloud& points, double voxel_size, double min_range);

}  // namespace strata

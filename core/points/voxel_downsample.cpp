#include "core/points/voxel_downsample.hpp"

#include "core/points/voxel_key.hpp"
#include "core/points/voxel_key_map.hpp"

namespace strata {

PointCloud voxel_downsample(const PointCloud& points, double voxel_size) {
  if (voxel_size <= 0.0)
    return points;
  return voxel_downsample(points, voxel_size, 0.0);
}

PointCloud voxel_downsample(const PointCloud& points, double voxel_size, double min_range) {
  const double min_squared = min_range > 0.0 ? min_range * min_range : -1.0;
  if (voxel_size <= 0.0) {
    PointCloud kept;
    kept.reserve(points.size());
    for (const Eigen::Vector3d& p : points) {
      if (p.squaredNorm() >= min_squared)
        kept.push_back(p);
    }
    return kept;
  }
  const double inverse = 1.0 / voxel_size;
  // Sized for a quarter of the points (scans thin by 3-40x); it grows where one thins less.
  VoxelKeyMap occupied(points.size() / 4);
  PointCloud kept;
  kept.reserve(points.size() / 4);
  for (const Eigen::Vector3d& p : points) {
    if (p.squaredNorm() >= min_squared && occupied.try_emplace(voxel_key(voxel_cell(p, inverse)), 0).second)
      kept.push_back(p);
  }
  return kept;
}

}  // namespace strata

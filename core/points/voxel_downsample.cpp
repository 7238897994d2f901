#include "core/points/voxel_downsample.hpp"

#include <unordered_set>

#include "core/points/voxel_key.hpp"

namespace strata {

PointCloud voxel_downsample(const PointCloud& points, double voxel_size) {
  if (voxel_size <= 0.0)
    return points;
  const double inverse = 1.0 / voxel_size;
  std::unordered_set<VoxelKey, VoxelKeyHash> occupied;
  occupied.reserve(points.size());
  PointCloud kept;
  kept.reserve(points.size() / 4);
  for (const Eigen::Vector3d& p : points) {
    if (occupied.insert(voxel_key(voxel_cell(p, inverse))).second)
      kept.push_back(p);
  }
  return kept;
}

}  // namespace strata

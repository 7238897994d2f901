#include "core/ann/voxel_hash_map.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace strata {

VoxelHashMap::VoxelHashMap(PointCloud points, double voxel_size) : inverse_voxel_size_(1.0 / voxel_size) {
  std::vector<std::pair<VoxelKey, std::uint32_t>> keyed;
  keyed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    keyed.emplace_back(voxel_key(voxel_cell(points[i], inverse_voxel_size_)), static_cast<std::uint32_t>(i));
  std::sort(keyed.begin(), keyed.end());
  points_.reserve(points.size());
  voxels_.reserve(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    points_.push_back(points[keyed[i].second]);
    const auto position = static_cast<std::uint32_t>(i);
    auto [it, inserted] = voxels_.try_emplace(keyed[i].first, Span{position, position + 1});
    if (!inserted)
      it->second.end = position + 1;
  }
}

std::optional<Neighbor> VoxelHashMap::nearest(const Eigen::Vector3d& query, double max_distance) const {
  const Eigen::Vector3i center = voxel_cell(query, inverse_voxel_size_);
  const int reach = static_cast<int>(std::ceil(max_distance * inverse_voxel_size_));
  double best_squared = max_distance * max_distance;
  std::optional<Neighbor> best;
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dz = -reach; dz <= reach; ++dz) {
        const auto found = voxels_.find(voxel_key(center + Eigen::Vector3i(dx, dy, dz)));
        if (found == voxels_.end())
          continue;
        for (std::uint32_t i = found->second.begin; i < found->second.end; ++i) {
          const double squared = (points_[i] - query).squaredNorm();
          if (squared <= best_squared) {
            best_squared = squared;
            best = Neighbor{i, squared};
          }
        }
      }
    }
  }
  return best;
}

}  // namespace strata

#include "core/localization/localization_map.hpp"

#include <cmath>
#include <cstdint>

#include "core/points/voxel_key.hpp"
#include "core/points/voxel_key_map.hpp"

namespace strata {

PointCloud LocalizationMap::cloud() const {
  PointCloud out;
  out.reserve(points.size());
  for (const Eigen::Vector3f& p : points)
    out.push_back(p.cast<double>());
  return out;
}

LocalizationMap make_localization_map(const std::vector<KeyframePose>& keyframes, double voxel) {
  LocalizationMap map;
  map.voxel = voxel;
  std::size_t total = 0;
  for (const KeyframePose& k : keyframes)
    total += k.keyframe->points.size();
  VoxelKeyMap seen(total / 2);
  const double inverse = 1.0 / voxel;
  for (const KeyframePose& k : keyframes) {
    map.keyframe_poses.push_back(k.pose);
    for (const Eigen::Vector3d& local : k.keyframe->points) {
      const Eigen::Vector3d p = k.pose * local;
      if (!p.allFinite())
        continue;
      if (seen.try_emplace(voxel_key(voxel_cell(p, inverse)), static_cast<std::uint32_t>(map.points.size()))
              .second)
        map.points.push_back(p.cast<float>());
    }
  }
  return map;
}

}  // namespace strata

#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/ann/neighbor.hpp"
#include "core/points/point_cloud.hpp"
#include "core/points/voxel_key.hpp"

namespace strata {

/// A hash of cubic voxels, each listing the cloud's points inside it; a bounded nearest search scans only
/// the voxels within the bound. Measured against the kd-tree in tests/bench/registration_bench.cpp: equal
/// at small bounds, slower at the metre-scale bounds the first ICP rounds use, so the kd-tree is the
/// default and this stays as the measured alternative.
class VoxelHashMap {
 public:
  VoxelHashMap(PointCloud points, double voxel_size);

  [[nodiscard]] std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double max_distance) const;
  [[nodiscard]] const PointCloud& points() const { return points_; }

 private:
  struct Span {
    std::uint32_t begin;
    std::uint32_t end;
  };
  PointCloud points_;  ///< sorted by voxel, so each voxel's points are contiguous
  double inverse_voxel_size_;
  std::unordered_map<VoxelKey, Span, VoxelKeyHash> voxels_;
};

}  // namespace strata

#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/ann/neighbor.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A static kd-tree over a point cloud it owns (nanoflann underneath). Chosen over a voxel hash and the
/// thesis octree by measurement (see tests/bench/registration_bench.cpp): it answers bounded nearest
/// queries at any radius, which the coarse-to-fine ICP needs, at the same speed as a voxel hash at small
/// radii.
class KdTree {
 public:
  explicit KdTree(PointCloud points);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;

  /// The closest point within `max_distance` of `query`, if any. The bound prunes the search (the thesis's
  /// trimming: pairs farther apart than this are not correspondences at all).
  [[nodiscard]] std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double max_distance) const;
  /// The `k` closest points (fewer if the cloud is smaller), nearest first.
  [[nodiscard]] std::vector<Neighbor> k_nearest(const Eigen::Vector3d& query, std::size_t k) const;

  [[nodiscard]] const PointCloud& points() const { return points_; }
  [[nodiscard]] std::size_t size() const { return points_.size(); }

 private:
  struct Index;
  PointCloud points_;
  std::unique_ptr<Index> index_;
};

}  // namespace strata

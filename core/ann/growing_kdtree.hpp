#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/ann/kdtree.hpp"
#include "core/ann/neighbor.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A kd-tree over a cloud that grows at its end (the localizer's local map, which appends each scan's new
/// voxels): the points appended since the last full build have a small tree of their own, and both are
/// searched; the whole is built again once the small one holds a quarter as many points as the large one.
/// A scan adds a few per cent of the local map, so most scans index only those instead of the whole map,
/// which was a third of a simulated lidar's scan path (docs/benchmarks.md, "The local map's index").
/// Indices are positions in points(), the same as one KdTree over the whole cloud would give.
class GrowingKdTree {
 public:
  GrowingKdTree() = default;
  explicit GrowingKdTree(PointCloud points);

  /// Appends `points` at the end of the cloud and indexes them.
  void append(std::span<const Eigen::Vector3d> points);

  /// As KdTree's: the closest point within `max_distance`.
  [[nodiscard]] std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double max_distance) const;
  /// As KdTree's: the closest two within `max_distance`; `hint`: a nearby query's answer.
  [[nodiscard]] NearestTwo nearest_two(const Eigen::Vector3d& query, double max_distance,
                                       const NearestTwo& hint = {}) const;
  /// As KdTree's: the `k` closest, nearest first, into `out`.
  void k_nearest(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const;

  [[nodiscard]] const PointCloud& points() const { return points_; }
  [[nodiscard]] std::size_t size() const { return points_.size(); }
  /// Full builds so far (the first one's included), for the benchmarks.
  [[nodiscard]] std::size_t full_builds() const { return full_builds_; }

 private:
  void build_all();

  PointCloud points_;
  std::unique_ptr<KdTree> main_;    ///< over points_[0, main_->size())
  std::unique_ptr<KdTree> recent_;  ///< over the rest, if any
  std::size_t full_builds_ = 0;
};

}  // namespace strata

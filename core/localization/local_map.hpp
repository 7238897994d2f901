#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/points/normals.hpp"
#include "core/points/point_cloud.hpp"
#include "core/points/voxel_key_map.hpp"

namespace strata {

/// The localizer's model set: the last few registered scans as one voxel map, one point per voxel (the
/// first that fell into it). Adding a scan marks every voxel it reaches as seen now; a voxel no scan has
/// reached in the last `scans` scans expires (KISS-ICP's local map, aged by scan instead of by distance).
/// The same voxels as thinning the concatenation of the last `scans` scans, but each scan is hashed once,
/// when it comes, instead of all of them again for every new scan.
class LocalMap {
 public:
  LocalMap(double voxel_size, std::size_t scans);

  /// Adds a registered scan (map frame) and expires what it leaves too old.
  void add(const PointCloud& points);
  /// Moves every point by `transform` (the map frame was corrected): the voxels are hashed again, two
  /// points in one voxel keep the older, and the normals are estimated afresh.
  void transform(const Eigen::Isometry3d& transform);

  /// One point per live voxel, oldest voxels first.
  [[nodiscard]] const PointCloud& points() const { return points_; }
  [[nodiscard]] bool empty() const { return points_.empty(); }
  [[nodiscard]] std::size_t size() const { return points_.size(); }

  /// Normals estimated for the points so far, moved out (for a registration against points()), and back
  /// in once the registration estimated more: a point's normal is estimated once while it lives, not
  /// once per scan. Estimates that do not match points() are dropped.
  [[nodiscard]] LazyNormals::Estimates take_normals() { return std::move(normals_); }
  void keep_normals(LazyNormals::Estimates normals);

 private:
  void expire();

  double inverse_voxel_size_;
  std::size_t scans_;
  std::uint32_t scan_ = 0;           ///< scans added so far
  PointCloud points_;                ///< per live voxel
  std::vector<std::uint32_t> seen_;  ///< per live voxel: the last scan that reached it
  VoxelKeyMap voxels_;               ///< voxel -> its index in points_
  LazyNormals::Estimates normals_;   ///< per live voxel, when known
};

}  // namespace strata

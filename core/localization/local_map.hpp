#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/points/point_cloud.hpp"
#include "core/points/voxel_key_map.hpp"
#include "core/registration/normals.hpp"

namespace strata {

/// The localizer's model set: the recent registered scans as one voxel map, one point per voxel (the
/// first that fell into it). Adding a scan marks every voxel it reaches as seen now; a voxel expires when
/// no scan has reached it in the last `scans` scans *and* the sensor has moved `metres` since one did
/// (KISS-ICP's local map is aged by distance alone). By scans alone a 10 Hz lidar forgot in one second the
/// ground rings it had passed, and its height walked 0.35 m in 60 s on flat ground; by distance it keeps
/// the ground it drove over, whatever the scan rate. Each scan is hashed once, when it comes. Back on a
/// way driven before, the earlier pass's points join it (join(), GraphLocalizerOptions::
/// earlier_pass_radius).
///
/// New voxels go at the end and the points keep their places until expired ones make up a quarter of the
/// map: only then are they dropped and the rest moved together (layout() changes). Until then the expired
/// points stay in points(), old surfaces as real as the rest, and a registration that follows the map
/// (ScanRegistration::follow_target) indexes only what each scan added.
class LocalMap {
 public:
  LocalMap(double voxel_size, std::size_t scans, double metres = 0.0);

  /// Adds a registered scan, its points and its `sensor` in the scan's own frame placed in the map frame by
  /// `map_from_scan`, and expires what it leaves too old.
  void add(const PointCloud& scan, const Eigen::Isometry3d& map_from_scan, const Eigen::Vector3d& sensor);
  /// The same for points and a sensor already in the map frame.
  void add(const PointCloud& points, const Eigen::Vector3d& sensor) {
    add(points, Eigen::Isometry3d::Identity(), sensor);
  }
  /// Points an earlier pass saw (a keyframe's, at its pose now) join the map as if the latest scan had
  /// reached them: voxels no scan of this pass reached take them, and they expire with that scan. Nothing
  /// before the first scan.
  void join(const PointCloud& points, const Eigen::Isometry3d& map_from_scan, const Eigen::Vector3d& sensor);
  /// Moves every point by `transform` (the map frame was corrected): the voxels are hashed again, two
  /// points in one voxel keep the older, and the normals are estimated afresh.
  void transform(const Eigen::Isometry3d& transform);

  /// One point per voxel, oldest voxels first (expired ones until they are dropped, above).
  [[nodiscard]] const PointCloud& points() const { return points_; }
  /// Per point: where the sensor was that first saw it.
  [[nodiscard]] const std::vector<Eigen::Vector3d>& viewpoints() const { return viewpoints_; }
  [[nodiscard]] bool empty() const { return points_.empty(); }
  [[nodiscard]] std::size_t size() const { return points_.size(); }
  /// Changes whenever points move or go (expired ones dropped, transform()); between two changes the
  /// points only grow at the end.
  [[nodiscard]] std::uint64_t layout() const { return layout_; }

  /// Normals estimated for the points so far, moved out (for a registration against points()), and back
  /// in once the registration estimated more: a point's normal is estimated once while it lives, not
  /// once per scan. Estimates that do not match points() are dropped.
  [[nodiscard]] LazyNormals::Estimates take_normals() { return std::move(normals_); }
  void keep_normals(LazyNormals::Estimates normals);

 private:
  /// A scan some voxel may still name as the last to reach it.
  struct ScanRecord {
    double travelled = 0.0;    ///< travelled_ when it was added
    std::uint32_t voxels = 0;  ///< voxels it was the last scan to reach
  };

  /// Marks the voxels of `points` (map frame by `map_from_scan`) reached by the latest scan, giving new
  /// voxels their point, seen from `sensor_in_map`.
  void reach(const PointCloud& points, const Eigen::Isometry3d& map_from_scan,
             const Eigen::Vector3d& sensor_in_map);
  void expire();
  /// Drops the voxels last reached before live_from_.
  void compact();
  [[nodiscard]] ScanRecord& record(std::uint32_t scan) { return records_[scan - first_record_]; }
  /// Counts the voxels per last scan afresh (after two voxels merged).
  void recount();

  double inverse_voxel_size_;
  std::size_t scans_;
  double metres_;
  std::uint32_t scan_ = 0;  ///< scans added so far
  double travelled_ = 0.0;  ///< metres the sensor moved between the scans added so far
  std::optional<Eigen::Vector3d> last_sensor_;
  std::uint64_t layout_ = 0;
  PointCloud points_;                        ///< per live voxel
  std::vector<std::uint32_t> seen_;          ///< per live voxel: the last scan that reached it
  std::vector<Eigen::Vector3d> viewpoints_;  ///< per live voxel: the sensor that first saw its point
  VoxelKeyMap voxels_;                       ///< voxel -> its index in points_
  LazyNormals::Estimates normals_;           ///< per live voxel, when known
  // Whether a voxel has expired depends only on its last scan, and an older scan expires no later than a
  // newer one: the expired voxels are those last reached before one scan, live_from_. Counting them per
  // scan spares a pass over the whole map at every scan to decide whether to compact it.
  std::vector<ScanRecord> records_;  ///< scans first_record_, first_record_ + 1, ..., scan_
  std::uint32_t first_record_ = 1;
  std::uint32_t live_from_ = 1;
  std::size_t expired_ = 0;  ///< voxels last reached before live_from_
};

}  // namespace strata

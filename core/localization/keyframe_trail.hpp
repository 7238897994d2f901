#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "core/localization/keyframe.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// The registered scans since the newest keyframe, which the next keyframe keeps for rebuilding the map
/// (Keyframe::scans). Each is held relative to the newest keyframe, which a pose graph correction of the
/// scan path's frame leaves unchanged. Scan path only.
class KeyframeTrail {
 public:
  /// `voxel`: one point per voxel of this size, metres (the map's cell); 0 keeps nothing.
  explicit KeyframeTrail(double voxel);

  /// A registered scan that did not make a keyframe: `points` and `sensor_origin` in its base frame,
  /// `keyframe_from_scan` its pose relative to the newest keyframe.
  void add(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
           const Eigen::Isometry3d& keyframe_from_scan);

  /// One point per voxel of the trail's size, the first in each, in the scan's order: what a scan keeps.
  [[nodiscard]] PointCloud thin(const PointCloud& points) const;
  /// A new keyframe's scans: the trail and then its own scan (`thinned`: thin() of it, `sensor_origin`),
  /// in its base frame, thinned over them all; `previous_from_keyframe` its pose relative to the previous
  /// keyframe. Empties the trail.
  [[nodiscard]] std::vector<KeyframeScan> close(const PointCloud& thinned,
                                                const Eigen::Vector3d& sensor_origin,
                                                const Eigen::Isometry3d& previous_from_keyframe);
  [[nodiscard]] double voxel() const { return voxel_; }

  [[nodiscard]] std::size_t size() const { return scans_.size(); }

 private:
  struct Scan {
    PointCloud points;  ///< thinned, in the scan's base frame
    Eigen::Vector3d sensor_origin;
    Eigen::Isometry3d keyframe_from_scan;
  };

  double voxel_;
  std::vector<Scan> scans_;
};

}  // namespace strata

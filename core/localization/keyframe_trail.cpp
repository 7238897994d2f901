#include "core/localization/keyframe_trail.hpp"

#include <utility>

#include "core/points/voxel_downsample.hpp"
#include "core/points/voxel_key.hpp"
#include "core/points/voxel_key_set.hpp"

namespace strata {

KeyframeTrail::KeyframeTrail(double voxel) : voxel_(voxel) {}

PointCloud KeyframeTrail::thin(const PointCloud& points) const {
  return voxel_ > 0.0 ? voxel_downsample(points, voxel_) : PointCloud{};
}

void KeyframeTrail::add(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
                        const Eigen::Isometry3d& keyframe_from_scan) {
  if (voxel_ > 0.0)
    scans_.push_back({thin(points), sensor_origin, keyframe_from_scan});
}

std::vector<KeyframeScan> KeyframeTrail::close(const PointCloud& thinned,
                                               const Eigen::Vector3d& sensor_origin,
                                               const Eigen::Isometry3d& previous_from_keyframe) {
  std::vector<KeyframeScan> kept;
  if (voxel_ <= 0.0)
    return kept;
  if (scans_.empty()) {  // a keyframe every scan (a fast lidar): its own voxels are distinct already
    KeyframeScan own;
    own.sensor_origin = sensor_origin.cast<float>();
    own.ground = Eigen::Vector3f::Zero();
    own.points.reserve(thinned.size());
    for (const Eigen::Vector3d& p : thinned)
      own.points.push_back(p.cast<float>());
    kept.push_back(std::move(own));
    return kept;
  }
  const double inverse_voxel = 1.0 / voxel_;
  // The flat map, not std::unordered_set, whose node per voxel doubled this step's instructions on the
  // HDL-32E capture (a car: a keyframe every revolution).
  std::size_t expected = thinned.size();
  for (const Scan& scan : scans_)
    expected += scan.points.size();
  VoxelKeySet reached(expected);
  const auto keep = [&](const PointCloud& scan_points, const Eigen::Vector3d& origin,
                        const Eigen::Isometry3d& keyframe_from_scan) {
    KeyframeScan scan;
    scan.sensor_origin = (keyframe_from_scan * origin).cast<float>();
    scan.ground = keyframe_from_scan.translation().cast<float>();
    for (const Eigen::Vector3d& p : scan_points) {
      const Eigen::Vector3d q = keyframe_from_scan * p;
      if (reached.insert(voxel_key(voxel_cell(q, inverse_voxel))))
        scan.points.push_back(q.cast<float>());
    }
    kept.push_back(std::move(scan));
  };
  kept.reserve(scans_.size() + 1);
  const Eigen::Isometry3d keyframe_from_previous = previous_from_keyframe.inverse();
  for (const Scan& scan : scans_)
    keep(scan.points, scan.sensor_origin, keyframe_from_previous * scan.keyframe_from_scan);
  keep(thinned, sensor_origin, Eigen::Isometry3d::Identity());
  scans_.clear();
  return kept;
}

}  // namespace strata

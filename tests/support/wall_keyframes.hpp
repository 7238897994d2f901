#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <utility>
#include <vector>

#include "core/localization/keyframe.hpp"

namespace strata::testing {

/// What a sensor 1 m above the floor sees standing at the origin of a room: floor from x = 0.5 to 2.5 m
/// and a wall at x = 3 m, 1.5 m high (base frame, 5 cm apart).
inline PointCloud room_seen_from_origin() {
  PointCloud points;
  for (double y = -1.5; y <= 1.5; y += 0.05) {
    for (double x = 0.5; x <= 2.5; x += 0.05)
      points.emplace_back(x, y, 0.0);
    for (double z = 0.05; z <= 1.5; z += 0.05)
      points.emplace_back(3.0, y, z);
  }
  return points;
}

/// A keyframe of that view, put into the live map at `mapped_pose`.
inline KeyframePtr room_keyframe(const Eigen::Isometry3d& mapped_pose, double stamp) {
  auto keyframe = std::make_shared<Keyframe>();
  keyframe->stamp = stamp;
  keyframe->points = room_seen_from_origin();
  KeyframeScan scan;
  scan.sensor_origin = Eigen::Vector3f(0.0F, 0.0F, 1.0F);
  for (const Eigen::Vector3d& p : keyframe->points)
    scan.points.push_back(p.cast<float>());
  keyframe->scans.push_back(std::move(scan));
  keyframe->mapped_pose = mapped_pose;
  return keyframe;
}

}  // namespace strata::testing

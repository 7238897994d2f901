#include "server/pipeline/map_rebuilder.hpp"

#include <algorithm>
#include <utility>

namespace strata::pipeline {

MapRebuilder::MapRebuilder(MlsConfig config, MapRebuildOptions options)
    : config_(std::move(config)), options_(options) {}

const Eigen::Isometry3d& MapRebuilder::in_map(const KeyframePtr& keyframe) const {
  const auto found = rebuilt_at_.find(keyframe);
  return found != rebuilt_at_.end() ? found->second : keyframe->mapped_pose;
}

KeyframeMoves MapRebuilder::moves(const std::vector<KeyframePose>& keyframes) const {
  KeyframeMoves moves;
  moves.keyframes = keyframes.size();
  for (const auto& [keyframe, pose] : keyframes) {
    const Eigen::Isometry3d& before = in_map(keyframe);
    const double shift = (pose.translation() - before.translation()).norm();
    const double turn = Eigen::AngleAxisd(before.linear().transpose() * pose.linear()).angle();
    moves.largest_shift = std::max(moves.largest_shift, shift);
    if (shift >= options_.min_shift || turn >= options_.min_turn)
      ++moves.moved;
  }
  return moves;
}

MlsMap MapRebuilder::build(const std::vector<KeyframePose>& keyframes) const {
  MlsMap map(config_);
  PointCloud points;
  for (const auto& [keyframe, pose] : keyframes) {
    for (const KeyframeScan& scan : keyframe->scans) {
      points.clear();
      points.reserve(scan.points.size());
      for (const Eigen::Vector3f& p : scan.points)
        points.push_back(pose * p.cast<double>());
      map.insert_scan(points, pose * scan.sensor_origin.cast<double>(), pose * scan.ground.cast<double>());
    }
  }
  return map;
}

void MapRebuilder::landed(const std::vector<KeyframePose>& keyframes) {
  for (const auto& [keyframe, pose] : keyframes)
    rebuilt_at_[keyframe] = pose;
}

}  // namespace strata::pipeline

#include "core/localization/local_map.hpp"

#include <algorithm>

#include "core/points/voxel_key.hpp"

namespace strata {
namespace {

/// Expired points are dropped once they make up this share of the map (1 / 4): compacting moves every
/// point, hashes the map again and makes the registration index it anew, which every scan did before
/// (docs/benchmarks.md, "The local map's index").
constexpr std::size_t kCompactionShareDivisor = 4;

}  // namespace

LocalMap::LocalMap(double voxel_size, std::size_t scans, double metres)
    : inverse_voxel_size_(1.0 / voxel_size), scans_(scans), metres_(metres) {}

void LocalMap::keep_normals(LazyNormals::Estimates normals) {
  if (normals.normals.size() == points_.size() && normals.states.size() == points_.size())
    normals_ = std::move(normals);
  else
    normals_ = {};
}

void LocalMap::add(const PointCloud& points, const Eigen::Vector3d& sensor) {
  ++scan_;
  if (last_sensor_)
    travelled_ += (sensor - *last_sensor_).norm();
  last_sensor_ = sensor;
  for (const Eigen::Vector3d& p : points) {
    const auto next = static_cast<std::uint32_t>(points_.size());
    const auto [index, added] = voxels_.try_emplace(voxel_key(voxel_cell(p, inverse_voxel_size_)), next);
    if (added) {
      points_.push_back(p);
      viewpoints_.push_back(sensor);
      seen_.push_back(scan_);
      seen_at_.push_back(travelled_);
    } else {
      seen_[index] = scan_;
      seen_at_[index] = travelled_;
    }
  }
  if (!normals_.states.empty()) {  // the new voxels have none yet
    normals_.normals.resize(points_.size());
    normals_.states.resize(points_.size(), LazyNormals::State::kUnknown);
  }
  expire();
}

void LocalMap::transform(const Eigen::Isometry3d& transform) {
  ++layout_;
  const PointCloud moved = transformed(points_, transform);
  const std::vector<std::uint32_t> seen = seen_;
  const std::vector<double> seen_at = seen_at_;
  const std::vector<Eigen::Vector3d> viewpoints = viewpoints_;
  points_.clear();
  viewpoints_.clear();
  seen_.clear();
  seen_at_.clear();
  voxels_.clear();
  normals_ = {};
  for (std::size_t i = 0; i < moved.size(); ++i) {
    const auto next = static_cast<std::uint32_t>(points_.size());
    const auto [index, added] =
        voxels_.try_emplace(voxel_key(voxel_cell(moved[i], inverse_voxel_size_)), next);
    if (added) {
      points_.push_back(moved[i]);
      viewpoints_.push_back(transform * viewpoints[i]);
      seen_.push_back(seen[i]);
      seen_at_.push_back(seen_at[i]);
    } else {
      seen_[index] = std::max(seen_[index], seen[i]);
      seen_at_[index] = std::max(seen_at_[index], seen_at[i]);
    }
  }
}

void LocalMap::expire() {
  if (scan_ <= scans_)
    return;
  const std::uint32_t oldest_kept = scan_ - static_cast<std::uint32_t>(scans_) + 1;
  const auto live = [&](std::size_t i) {
    return seen_[i] >= oldest_kept || (metres_ > 0.0 && travelled_ - seen_at_[i] <= metres_);
  };
  std::size_t expired = 0;
  for (std::size_t i = 0; i < points_.size(); ++i)
    expired += live(i) ? 0 : 1;
  if (expired == 0 || expired * kCompactionShareDivisor < points_.size())
    return;  // not worth moving every point and hashing the map again for
  ++layout_;
  std::size_t kept = 0;
  const bool normals = !normals_.states.empty();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (live(i)) {
      points_[kept] = points_[i];
      viewpoints_[kept] = viewpoints_[i];
      seen_[kept] = seen_[i];
      seen_at_[kept] = seen_at_[i];
      if (normals) {
        normals_.normals[kept] = normals_.normals[i];
        normals_.states[kept] = normals_.states[i];
      }
      ++kept;
    }
  }
  points_.resize(kept);
  viewpoints_.resize(kept);
  seen_.resize(kept);
  seen_at_.resize(kept);
  if (normals) {
    normals_.normals.resize(kept);
    normals_.states.resize(kept);
  }
  // The map holds indices into points_, which just moved: hash the survivors again (a pass over the
  // live voxels, no scan's points).
  voxels_.clear();
  for (std::size_t i = 0; i < points_.size(); ++i)
    voxels_.try_emplace(voxel_key(voxel_cell(points_[i], inverse_voxel_size_)),
                        static_cast<std::uint32_t>(i));
}

}  // namespace strata

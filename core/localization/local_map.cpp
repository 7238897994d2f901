#include "core/localization/local_map.hpp"

#include <algorithm>
#include <array>

#include "core/points/voxel_key.hpp"

namespace strata {
namespace {

/// Expired points are dropped once they make up this share of the map (1 / 4): compacting moves every
/// point, hashes the map again and makes the registration index it anew, which every scan did before
/// (docs/benchmarks.md, "The local map's index").
constexpr std::size_t kCompactionShareDivisor = 4;

/// Points whose voxels are asked of memory before the first of them is looked up.
constexpr std::size_t kLookAhead = 8;

/// Calls visit(i, point, key) for the points point_at(0), ..., point_at(count - 1) in order, each with its
/// voxel's key, the voxel asked of memory kLookAhead points before it is visited: a map of a few hundred
/// thousand voxels is tens of megabytes, and each lookup otherwise waited for memory.
template <class PointAt, class Visit>
void for_each_voxel(const VoxelKeyMap& voxels, double inverse_voxel_size, std::size_t count, PointAt point_at,
                    Visit visit) {
  struct Ahead {
    Eigen::Vector3d point;
    VoxelKey key = 0;
  };
  std::array<Ahead, kLookAhead> ahead;
  const auto ask = [&](std::size_t i) {
    Ahead& a = ahead[i % kLookAhead];
    a.point = point_at(i);
    a.key = voxel_key(voxel_cell(a.point, inverse_voxel_size));
    voxels.prefetch(a.key);
  };
  for (std::size_t i = 0; i < std::min(count, kLookAhead); ++i)
    ask(i);
  for (std::size_t i = 0; i < count; ++i) {
    const Ahead a = ahead[i % kLookAhead];
    if (i + kLookAhead < count)
      ask(i + kLookAhead);
    visit(i, a.point, a.key);
  }
}

}  // namespace

LocalMap::LocalMap(double voxel_size, std::size_t scans, double metres)
    : inverse_voxel_size_(1.0 / voxel_size), scans_(scans), metres_(metres) {}

void LocalMap::keep_normals(LazyNormals::Estimates normals) {
  if (normals.normals.size() == points_.size() && normals.states.size() == points_.size())
    normals_ = std::move(normals);
  else
    normals_ = {};
}

void LocalMap::add(const PointCloud& scan, const Eigen::Isometry3d& map_from_scan,
                   const Eigen::Vector3d& sensor) {
  const Eigen::Vector3d sensor_in_map = map_from_scan * sensor;
  ++scan_;
  if (last_sensor_)
    travelled_ += (sensor_in_map - *last_sensor_).norm();
  last_sensor_ = sensor_in_map;
  records_.push_back({.travelled = travelled_, .voxels = 0});
  reach(scan, map_from_scan, sensor_in_map);
  expire();
}

void LocalMap::join(const PointCloud& points, const Eigen::Isometry3d& map_from_scan,
                    const Eigen::Vector3d& sensor) {
  if (records_.empty())
    return;
  reach(points, map_from_scan, map_from_scan * sensor);
}

void LocalMap::reach(const PointCloud& points, const Eigen::Isometry3d& map_from_scan,
                     const Eigen::Vector3d& sensor_in_map) {
  std::uint32_t& reached_now = records_.back().voxels;
  for_each_voxel(
      voxels_, inverse_voxel_size_, points.size(), [&](std::size_t i) { return map_from_scan * points[i]; },
      [&](std::size_t, const Eigen::Vector3d& p, VoxelKey key) {
        const auto next = static_cast<std::uint32_t>(points_.size());
        const auto [index, added] = voxels_.try_emplace(key, next);
        if (added) {
          points_.push_back(p);
          viewpoints_.push_back(sensor_in_map);
          seen_.push_back(scan_);
          ++reached_now;
        } else if (const std::uint32_t last = seen_[index]; last != scan_) {
          --record(last).voxels;
          expired_ -= last < live_from_ ? 1 : 0;
          seen_[index] = scan_;
          ++reached_now;
        }
      });
  if (!normals_.states.empty()) {  // the new voxels have none yet
    normals_.normals.resize(points_.size());
    normals_.states.resize(points_.size(), LazyNormals::State::kUnknown);
  }
}

void LocalMap::transform(const Eigen::Isometry3d& transform) {
  ++layout_;
  voxels_.clear();
  normals_ = {};
  // In place: a point moves to an index no later than its own.
  std::size_t kept = 0;
  for_each_voxel(
      voxels_, inverse_voxel_size_, points_.size(), [&](std::size_t i) { return transform * points_[i]; },
      [&](std::size_t i, const Eigen::Vector3d& moved, VoxelKey key) {
        const auto [index, added] = voxels_.try_emplace(key, static_cast<std::uint32_t>(kept));
        if (added) {
          points_[kept] = moved;
          viewpoints_[kept] = transform * viewpoints_[i];
          seen_[kept] = seen_[i];
          ++kept;
        } else {
          seen_[index] = std::max(seen_[index], seen_[i]);
        }
      });
  points_.resize(kept);
  viewpoints_.resize(kept);
  seen_.resize(kept);
  recount();
}

void LocalMap::recount() {
  for (ScanRecord& r : records_)
    r.voxels = 0;
  for (const std::uint32_t last : seen_)
    ++record(last).voxels;
  expired_ = 0;
  for (std::uint32_t scan = first_record_; scan < live_from_; ++scan)
    expired_ += record(scan).voxels;
}

void LocalMap::expire() {
  if (scan_ <= scans_)
    return;
  // Scans no voxel names any more (all reached again since) say nothing: dropped, so that a sensor standing
  // still, which expires nothing, keeps no record per scan.
  std::size_t unnamed = 0;
  while (first_record_ + unnamed < scan_ && records_[unnamed].voxels == 0)
    ++unnamed;
  records_.erase(records_.begin(), records_.begin() + static_cast<std::ptrdiff_t>(unnamed));
  first_record_ += static_cast<std::uint32_t>(unnamed);
  live_from_ = std::max(live_from_, first_record_);
  const std::uint32_t oldest_kept = scan_ - static_cast<std::uint32_t>(scans_) + 1;
  while (live_from_ < oldest_kept &&
         !(metres_ > 0.0 && travelled_ - record(live_from_).travelled <= metres_)) {
    expired_ += record(live_from_).voxels;
    ++live_from_;
  }
  if (expired_ == 0 || expired_ * kCompactionShareDivisor < points_.size())
    return;  // not worth moving every point and hashing the map again for
  compact();
}

void LocalMap::compact() {
  ++layout_;
  std::size_t kept = 0;
  const bool normals = !normals_.states.empty();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (seen_[i] >= live_from_) {
      points_[kept] = points_[i];
      viewpoints_[kept] = viewpoints_[i];
      seen_[kept] = seen_[i];
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
  if (normals) {
    normals_.normals.resize(kept);
    normals_.states.resize(kept);
  }
  // No voxel names an expired scan any more.
  records_.erase(records_.begin(), records_.begin() + (live_from_ - first_record_));
  first_record_ = live_from_;
  expired_ = 0;
  // The map holds indices into points_, which just moved: hash the survivors again (a pass over the
  // live voxels, no scan's points).
  voxels_.clear();
  for_each_voxel(
      voxels_, inverse_voxel_size_, points_.size(), [&](std::size_t i) { return points_[i]; },
      [&](std::size_t i, const Eigen::Vector3d&, VoxelKey key) {
        voxels_.try_emplace(key, static_cast<std::uint32_t>(i));
      });
}

}  // namespace strata

#include "core/ann/growing_kdtree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace strata {
namespace {

/// The recent points' tree is folded into a full build once it holds this share of the main tree's
/// points: each query searches both, and a larger small tree costs every query more than it saves.
constexpr std::size_t kRecentShareDivisor = 4;

std::optional<Neighbor> shifted(std::optional<Neighbor> neighbor, std::size_t offset) {
  if (neighbor)
    neighbor->index += offset;
  return neighbor;
}

}  // namespace

GrowingKdTree::GrowingKdTree(PointCloud points) : points_(std::move(points)) {
  build_all();
}

void GrowingKdTree::build_all() {
  main_ = std::make_unique<KdTree>(points_);
  recent_.reset();
  ++full_builds_;
}

void GrowingKdTree::append(std::span<const Eigen::Vector3d> points) {
  if (points.empty())
    return;
  points_.insert(points_.end(), points.begin(), points.end());
  const std::size_t indexed = main_ ? main_->size() : 0;
  const std::size_t recent = points_.size() - indexed;
  if (recent * kRecentShareDivisor > indexed) {
    build_all();
    return;
  }
  recent_ = std::make_unique<KdTree>(
      PointCloud(points_.begin() + static_cast<std::ptrdiff_t>(indexed), points_.end()));
}

std::optional<Neighbor> GrowingKdTree::nearest(const Eigen::Vector3d& query, double max_distance) const {
  std::optional<Neighbor> best = main_ ? main_->nearest(query, max_distance) : std::nullopt;
  if (recent_) {
    const double bound = best ? std::sqrt(best->squared_distance) : max_distance;
    std::optional<Neighbor> other = shifted(recent_->nearest(query, bound), main_->size());
    if (other && (!best || other->squared_distance < best->squared_distance))
      best = other;
  }
  return best;
}

NearestTwo GrowingKdTree::nearest_two(const Eigen::Vector3d& query, double max_distance,
                                      const NearestTwo& hint) const {
  if (!main_)
    return {};
  if (!recent_)
    return main_->nearest_two(query, max_distance, hint);
  const std::size_t split = main_->size();
  // Each tree gets the hints that are its own points.
  NearestTwo main_hint;
  NearestTwo recent_hint;
  for (const std::optional<Neighbor>& known : {hint.first, hint.second}) {
    if (!known)
      continue;
    NearestTwo& into = known->index < split ? main_hint : recent_hint;
    const Neighbor local{known->index < split ? known->index : known->index - split, 0.0};
    (into.first ? into.second : into.first) = local;
  }
  const NearestTwo in_main = main_->nearest_two(query, max_distance, main_hint);
  // The recent points only matter where they come closer than the main tree's second.
  const double bound = in_main.second ? std::sqrt(in_main.second->squared_distance) : max_distance;
  const NearestTwo in_recent = recent_->nearest_two(query, bound, recent_hint);
  std::array<std::optional<Neighbor>, 4> found = {
      in_main.first, in_main.second, shifted(in_recent.first, split), shifted(in_recent.second, split)};
  std::sort(found.begin(), found.end(),
            [](const std::optional<Neighbor>& a, const std::optional<Neighbor>& b) {
              if (!a || !b)
                return a.has_value() && !b.has_value();
              return a->squared_distance < b->squared_distance;
            });
  return {found[0], found[1]};
}

void GrowingKdTree::k_nearest(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const {
  out.clear();
  if (!main_)
    return;
  main_->k_nearest(query, k, out);
  if (!recent_)
    return;
  // Scratch per thread (the normals are estimated on several, each through here for every point): no
  // allocation per query.
  thread_local std::vector<Neighbor> in_main;
  thread_local std::vector<Neighbor> in_recent;
  in_main.swap(out);
  // The recent points only matter where they come closer than the main tree's k-th: unbounded, a query
  // far from every recent point searched half their tree for k of them (twice the normals' cost).
  const double bound = in_main.size() == k ? std::sqrt(in_main.back().squared_distance)
                                           : std::numeric_limits<double>::infinity();
  recent_->k_nearest(query, k, bound, in_recent);
  out.clear();
  std::size_t i = 0;
  std::size_t j = 0;
  while (out.size() < k && (i < in_main.size() || j < in_recent.size())) {
    if (j == in_recent.size() ||
        (i < in_main.size() && in_main[i].squared_distance <= in_recent[j].squared_distance)) {
      out.push_back(in_main[i++]);
    } else {
      out.push_back({in_recent[j].index + main_->size(), in_recent[j].squared_distance});
      ++j;
    }
  }
}

}  // namespace strata

#include "core/ann/kdtree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

namespace strata {
namespace {

/// Points per leaf: 6-24 measured within 5 % of each other (instructions per query and build, 80k real
/// points); 8 keeps a leaf in two cache lines of 16-byte points.
constexpr std::uint32_t kLeafSize = 8;

/// Levels split by cell (below), then by median: at most 32 more levels for 2^32 points.
constexpr int kMaxCellDepth = 48;

/// Float distances are compared against double bounds: widen the bound by this much (relative) so that
/// no point within it is lost to rounding, then decide membership in double.
constexpr double kBoundSlack = 1e-5;

float widened(double max_distance) {
  const double bound = max_distance * (1.0 + kBoundSlack);
  const double squared = bound * bound;
  return squared >= static_cast<double>(std::numeric_limits<float>::max())
             ? std::numeric_limits<float>::infinity()
             : static_cast<float>(squared);
}

/// The closest point.
class ClosestOne {
 public:
  explicit ClosestOne(float worst) : worst_(worst) {}
  [[nodiscard]] float worst() const { return worst_; }
  void add(float squared, std::uint32_t index) {
    worst_ = squared;
    index_ = index;
  }
  [[nodiscard]] std::optional<std::uint32_t> index() const {
    return index_ == kNone ? std::nullopt : std::optional(index_);
  }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  float worst_;
  std::uint32_t index_ = kNone;
};

/// The closest two; points already known (hints) may be offered again by the search and are not
/// counted twice.
class ClosestTwo {
 public:
  explicit ClosestTwo(float worst) : first_(worst), second_(worst) {}
  [[nodiscard]] float worst() const { return second_; }
  void add(float squared, std::uint32_t index) {
    if (index == first_index_ || index == second_index_)
      return;
    if (squared < first_) {
      second_ = first_;
      second_index_ = first_index_;
      first_ = squared;
      first_index_ = index;
    } else {
      second_ = squared;
      second_index_ = index;
    }
  }
  [[nodiscard]] std::optional<std::uint32_t> first() const {
    return first_index_ == kNone ? std::nullopt : std::optional(first_index_);
  }
  [[nodiscard]] std::optional<std::uint32_t> second() const {
    return second_index_ == kNone ? std::nullopt : std::optional(second_index_);
  }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  float first_;
  float second_;
  std::uint32_t first_index_ = kNone;
  std::uint32_t second_index_ = kNone;
};

/// The closest k, nearest first: a new point is inserted in order and the farthest falls off (k is small:
/// normals take 20).
class ClosestK {
 public:
  struct Entry {
    float squared;
    std::uint32_t index;
  };
  explicit ClosestK(std::size_t k, float bound = std::numeric_limits<float>::infinity())
      : k_(k), bound_(bound) {
    if (k_ > kInline)
      spill_.resize(k_);
  }
  [[nodiscard]] float worst() const { return found_ < k_ ? bound_ : entries()[k_ - 1].squared; }
  void add(float squared, std::uint32_t index) {
    Entry* e = entries();
    std::size_t slot = found_ < k_ ? found_++ : k_ - 1;
    for (; slot > 0 && e[slot - 1].squared > squared; --slot)
      e[slot] = e[slot - 1];
    e[slot] = {squared, index};
  }
  [[nodiscard]] std::span<const Entry> sorted() const { return {entries(), found_}; }

 private:
  static constexpr std::size_t kInline = 32;
  [[nodiscard]] Entry* entries() { return k_ > kInline ? spill_.data() : inline_.data(); }
  [[nodiscard]] const Entry* entries() const { return k_ > kInline ? spill_.data() : inline_.data(); }
  std::size_t k_;
  float bound_;  ///< squared: nothing farther counts
  std::size_t found_ = 0;
  std::array<Entry, kInline> inline_;
  std::vector<Entry> spill_;
};

}  // namespace

KdTree::KdTree(PointCloud points) : points_(std::move(points)) {
  if (points_.empty())
    return;
  Eigen::Vector3d low = points_.front();
  Eigen::Vector3d high = points_.front();
  for (const Eigen::Vector3d& p : points_) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  // Floats relative to the middle of the cloud: a map far from its frame's origin keeps its precision.
  origin_ = 0.5 * (low + high);
  leaves_.resize(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d p = points_[i] - origin_;
    leaves_[i] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                  std::bit_cast<float>(static_cast<std::uint32_t>(i))};
  }
  nodes_.reserve(points_.size() / 2 + 1);
  root_ = bounds(0, static_cast<std::uint32_t>(leaves_.size()));
  build(0, static_cast<std::uint32_t>(leaves_.size()), root_, root_, 0);
}

std::uint32_t KdTree::build(std::uint32_t begin, std::uint32_t end, const Box& cell, const Box& points,
                            int depth) {
  const auto node = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[node].first = begin;
    nodes_[node].axis = kLeaf;
    nodes_[node].count = static_cast<std::uint16_t>(end - begin);
    return node;
  }
  // Split the cell in the middle of its widest side (nanoflann's rule; among sides of equal length, the
  // one the points spread most along), not the points at their median: cells stay compact, so every axis
  // gets split and a query's distance to a cell is bounded along all three. Median splits of a wall never
  // cut across it, and a query a metre off the wall scanned every leaf within a metre along it (6x the
  // points per ICP query on the real scans). Past a depth only degenerate clouds reach (points bunched ever
  // closer), split at the median, which bounds the depth.
  int axis = -1;
  if (depth < kMaxCellDepth) {
    float widest = 0.0F;
    for (int a = 0; a < 3; ++a)
      widest = std::max(widest, cell.high[a] - cell.low[a]);
    float spread = 0.0F;
    for (int a = 0; a < 3; ++a) {
      const float side = cell.high[a] - cell.low[a];
      if (side >= (1.0F - 1e-5F) * widest && points.high[a] - points.low[a] > spread) {
        axis = a;
        spread = points.high[a] - points.low[a];
      }
    }
  }
  std::uint32_t middle = 0;
  float cut = 0.0F;
  Box left_points{};
  Box right_points{};
  if (axis >= 0) {
    cut = std::clamp(0.5F * (cell.low[axis] + cell.high[axis]), points.low[axis], points.high[axis]);
    middle = divide(begin, end, axis, cut, points.low[axis], points.high[axis], left_points, right_points);
  } else {  // all points equal (or too deep): halve them at the median of their widest spread
    axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (points.high[a] - points.low[a] > points.high[axis] - points.low[axis])
        axis = a;
    }
    middle = begin + (end - begin) / 2;
    const auto coordinate = [axis](const Leaf& p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
    std::nth_element(leaves_.begin() + begin, leaves_.begin() + middle, leaves_.begin() + end,
                     [&](const Leaf& a, const Leaf& b) { return coordinate(a) < coordinate(b); });
    cut = coordinate(leaves_[middle]);
    left_points = bounds(begin, middle);
    right_points = bounds(middle, end);
  }
  Box left_cell = cell;
  left_cell.high[axis] = cut;
  Box right_cell = cell;
  right_cell.low[axis] = cut;
  build(begin, middle, left_cell, left_points, depth + 1);
  const std::uint32_t right = build(middle, end, right_cell, right_points, depth + 1);
  nodes_[node].low = left_points.high[axis];
  nodes_[node].high = right_points.low[axis];
  nodes_[node].first = right;
  nodes_[node].axis = static_cast<std::uint16_t>(axis);
  return node;
}

KdTree::Box KdTree::bounds(std::uint32_t begin, std::uint32_t end) const {
  // Four lanes at a time (x, y, z and the tag, ignored): a fifth of the instructions of three scalar
  // minima and maxima, and this pass was half the build.
  using Lanes = Eigen::Array4f;
  Lanes low = Eigen::Map<const Lanes>(&leaves_[begin].x);
  Lanes high = low;
  for (std::uint32_t i = begin + 1; i < end; ++i) {
    const Eigen::Map<const Lanes> p(&leaves_[i].x);
    low = low.min(p);
    high = high.max(p);
  }
  return {{low[0], low[1], low[2]}, {high[0], high[1], high[2]}};
}

std::uint32_t KdTree::divide(std::uint32_t begin, std::uint32_t end, int axis, float cut, float low,
                             float high, Box& lower, Box& upper) {
  switch (axis) {
    case 0:
      return divide_along(
          begin, end, cut, low, high, [](const Leaf& p) { return p.x; }, lower, upper);
    case 1:
      return divide_along(
          begin, end, cut, low, high, [](const Leaf& p) { return p.y; }, lower, upper);
    default:
      return divide_along(
          begin, end, cut, low, high, [](const Leaf& p) { return p.z; }, lower, upper);
  }
}

template <class Coordinate>
std::uint32_t KdTree::divide_along(std::uint32_t begin, std::uint32_t end, float cut, float low, float high,
                                   Coordinate coordinate, Box& lower, Box& upper) {
  // The points at a cut clamped to their lowest go left, at their highest right; neither half is empty.
  // Where those points are many, the halves are evened out (nanoflann's rule), and bounded afresh.
  Leaf* const first = leaves_.data() + begin;
  Leaf* const last = leaves_.data() + end;
  const std::uint32_t half = (end - begin) / 2;
  std::uint32_t at = 0;
  std::uint32_t middle = 0;
  if (cut <= low) {
    at = static_cast<std::uint32_t>(
        partition(
            first, last, [&](const Leaf& p) { return coordinate(p) <= cut; }, lower, upper) -
        first);
    middle = std::min(at, half);
  } else {
    at = static_cast<std::uint32_t>(
        partition(
            first, last, [&](const Leaf& p) { return coordinate(p) < cut; }, lower, upper) -
        first);
    middle = cut >= high ? std::max(at, half) : at;
  }
  if (middle != at) {
    lower = bounds(begin, begin + middle);
    upper = bounds(begin + middle, end);
  }
  return begin + middle;
}

template <class Below>
KdTree::Leaf* KdTree::partition(Leaf* first, Leaf* last, Below below, Box& lower, Box& upper) {
  using Lanes = Eigen::Array4f;
  const float inf = std::numeric_limits<float>::infinity();
  Lanes lower_low = Lanes::Constant(inf);
  Lanes lower_high = Lanes::Constant(-inf);
  Lanes upper_low = lower_low;
  Lanes upper_high = lower_high;
  const auto extend = [](Lanes& low, Lanes& high, const Leaf& p) {
    const Eigen::Map<const Lanes> lanes(&p.x);
    low = low.min(lanes);
    high = high.max(lanes);
  };
  const auto finish = [&] {
    lower = {{lower_low[0], lower_low[1], lower_low[2]}, {lower_high[0], lower_high[1], lower_high[2]}};
    upper = {{upper_low[0], upper_low[1], upper_low[2]}, {upper_high[0], upper_high[1], upper_high[2]}};
    return first;
  };
  while (true) {
    for (;; ++first) {
      if (first == last)
        return finish();
      if (!below(*first))
        break;
      extend(lower_low, lower_high, *first);
    }
    --last;
    for (;; --last) {
      if (first == last) {
        extend(upper_low, upper_high, *first);
        return finish();
      }
      if (below(*last))
        break;
      extend(upper_low, upper_high, *last);
    }
    std::iter_swap(first, last);
    extend(lower_low, lower_high, *first);
    extend(upper_low, upper_high, *last);
    ++first;
  }
}

void KdTree::relative(const Eigen::Vector3d& query, float* out) const {
  const Eigen::Vector3d q = query - origin_;
  out[0] = static_cast<float>(q.x());
  out[1] = static_cast<float>(q.y());
  out[2] = static_cast<float>(q.z());
}

template <class Result>
void KdTree::scan(const Leaf* first, std::uint32_t count, const float* query, Result& result) {
  for (const Leaf* p = first; p != first + count; ++p) {
    const float dx = p->x - query[0];
    const float dy = p->y - query[1];
    const float dz = p->z - query[2];
    const float squared = dx * dx + dy * dy + dz * dz;
    if (squared < result.worst())
      result.add(squared, p->index());
  }
}

/// Depth first, nearer child first; a farther child waits on a stack with a lower bound of its distance to
/// the query -- the distance to its side of the split along the split's axis -- and is skipped when the
/// result's worst distance has fallen below that by the time it comes up. Summing the per-axis offsets
/// down the path (Arya and Mount's incremental distance) prunes a little more but cost more than it saved:
/// 32 % more instructions per query on the real scans.
template <class Result>
void KdTree::search(const float* query, Result& result) const {
  struct Pending {
    std::uint32_t node;
    float lower;
  };
  std::array<Pending, kMaxCellDepth + 32> pending;
  std::size_t waiting = 0;
  std::uint32_t node = 0;
  while (true) {
    const Node* n = &nodes_[node];
    while (n->axis != kLeaf) {
      const float v = query[n->axis];
      const float to_left = v - n->low;
      const float to_right = n->high - v;
      std::uint32_t near = node + 1;
      std::uint32_t far = n->first;
      float far_offset = to_right;
      if (to_left > to_right) {
        std::swap(near, far);
        far_offset = to_left;
      }
      const float far_lower = far_offset * far_offset;
      if (far_lower < result.worst())
        pending[waiting++] = {far, far_lower};
      node = near;
      n = &nodes_[node];
    }
    scan(leaves_.data() + n->first, n->count, query, result);
    do {
      if (waiting == 0)
        return;
      --waiting;
    } while (pending[waiting].lower >= result.worst());
    node = pending[waiting].node;
  }
}

std::optional<Neighbor> KdTree::nearest(const Eigen::Vector3d& query, double max_distance) const {
  if (points_.empty())
    return std::nullopt;
  float q[3];
  relative(query, q);
  ClosestOne result(widened(max_distance));
  search(q, result);
  if (!result.index())
    return std::nullopt;
  const double squared = (points_[*result.index()] - query).squaredNorm();
  if (squared > max_distance * max_distance)
    return std::nullopt;
  return Neighbor{*result.index(), squared};
}

NearestTwo KdTree::nearest_two(const Eigen::Vector3d& query, double max_distance,
                               const NearestTwo& hint) const {
  if (points_.empty())
    return {};
  float q[3];
  relative(query, q);
  ClosestTwo result(widened(max_distance));
  for (const std::optional<Neighbor>& known : {hint.first, hint.second}) {
    if (!known)
      continue;
    const Eigen::Vector3d d = points_[known->index] - query;
    const auto squared = static_cast<float>(d.squaredNorm());
    if (squared < result.worst())
      result.add(squared, static_cast<std::uint32_t>(known->index));
  }
  search(q, result);
  const double max_squared = max_distance * max_distance;
  NearestTwo two;
  for (const auto& [found, out] : {std::pair{result.first(), &two.first}, {result.second(), &two.second}}) {
    if (!found)
      continue;
    const double squared = (points_[*found] - query).squaredNorm();
    if (squared <= max_squared)
      *out = Neighbor{*found, squared};
  }
  if (!two.first && two.second)
    std::swap(two.first, two.second);
  return two;
}

std::vector<Neighbor> KdTree::k_nearest(const Eigen::Vector3d& query, std::size_t k) const {
  std::vector<Neighbor> neighbors;
  k_nearest(query, k, neighbors);
  return neighbors;
}

void KdTree::k_nearest(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const {
  k_nearest(query, k, std::numeric_limits<double>::infinity(), out);
}

void KdTree::k_nearest(const Eigen::Vector3d& query, std::size_t k, double max_distance,
                       std::vector<Neighbor>& out) const {
  out.clear();
  k = std::min(k, points_.size());
  if (k == 0)
    return;
  float q[3];
  relative(query, q);
  ClosestK result(k,
                  std::isinf(max_distance) ? std::numeric_limits<float>::infinity() : widened(max_distance));
  search(q, result);
  const double max_squared = max_distance * max_distance;
  for (const ClosestK::Entry& entry : result.sorted()) {
    const double squared = (points_[entry.index] - query).squaredNorm();
    if (squared <= max_squared)
      out.push_back({entry.index, squared});
  }
}

}  // namespace strata

#include "core/ann/kdtree.hpp"

#include <limits>
#include <nanoflann.hpp>

namespace strata {
namespace {

/// nanoflann's view of a PointCloud.
struct CloudAdaptor {
  const PointCloud* points;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return (*points)[index][static_cast<Eigen::Index>(dim)];
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox& /*unused*/) const {
    return false;
  }
};

using NanoflannTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudAdaptor>,
                                                          CloudAdaptor, 3, std::size_t>;

/// Keeps only the closest point, starting from the bound as the worst accepted distance so nanoflann
/// never descends into cells farther than the bound.
class BoundedNearest {
 public:
  using DistanceType = double;
  using IndexType = std::size_t;
  using CountType = std::size_t;

  explicit BoundedNearest(double max_squared) : worst_(max_squared) {}
  [[nodiscard]] bool full() const { return true; }
  bool addPoint(double squared, std::size_t index) {
    if (squared <= worst_) {
      worst_ = squared;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  [[nodiscard]] double worstDist() const { return worst_; }
  [[nodiscard]] std::optional<Neighbor> result() const {
    if (!found_)
      return std::nullopt;
    return Neighbor{index_, worst_};
  }

 private:
  double worst_;
  std::size_t index_ = 0;
  bool found_ = false;
};

}  // namespace

struct KdTree::Index {
  explicit Index(const PointCloud& points)
      : adaptor{&points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
  CloudAdaptor adaptor;
  NanoflannTree tree;
};

KdTree::KdTree(PointCloud points) : points_(std::move(points)), index_(std::make_unique<Index>(points_)) {}
KdTree::~KdTree() = default;
// Moving a std::vector keeps its heap buffer, so the index's pointer to points_ must follow the new owner.
KdTree::KdTree(KdTree&& other) noexcept : points_(std::move(other.points_)), index_(std::move(other.index_)) {
  if (index_)
    index_->adaptor.points = &points_;
}
KdTree& KdTree::operator=(KdTree&& other) noexcept {
  points_ = std::move(other.points_);
  index_ = std::move(other.index_);
  if (index_)
    index_->adaptor.points = &points_;
  return *this;
}

std::optional<Neighbor> KdTree::nearest(const Eigen::Vector3d& query, double max_distance) const {
  if (points_.empty())
    return std::nullopt;
  BoundedNearest result(max_distance * max_distance);
  index_->tree.findNeighbors(result, query.data(), nanoflann::SearchParams());
  return result.result();
}

std::vector<Neighbor> KdTree::k_nearest(const Eigen::Vector3d& query, std::size_t k) const {
  k = std::min(k, points_.size());
  std::vector<std::size_t> indices(k);
  std::vector<double> squared(k);
  nanoflann::KNNResultSet<double, std::size_t, std::size_t> result(k);
  result.init(indices.data(), squared.data());
  if (k > 0)
    index_->tree.findNeighbors(result, query.data(), nanoflann::SearchParams());
  std::vector<Neighbor> neighbors;
  neighbors.reserve(result.size());
  for (std::size_t i = 0; i < result.size(); ++i)
    neighbors.push_back({indices[i], squared[i]});
  return neighbors;
}

}  // namespace strata

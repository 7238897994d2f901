#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "core/ann/growing_kdtree.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A source point paired with its closest target point.
struct Correspondence {
  std::size_t source = 0;
  std::size_t target = 0;
};

/// Closest-point pairing over the iterations of one ICP run (thesis Algorithm 2, steps 1-2) that asks the
/// kd-tree only where the answer can have changed. Each search finds a point's two closest target points,
/// at distances d1 <= d2: until the point has moved (d2 - d1) / 2 from where it was searched, the first is
/// still its closest (triangle inequality), so the late iterations, which move the points by millimetres,
/// mostly reuse their partners. Exact: the pairs are the ones a full search gives (up to equidistant
/// points).
class PartnerSearch {
 public:
  /// Pairs within `max_distance` of each other with sources of `source_size` points; the kd-tree searches
  /// on up to `threads` threads (the caller's among them), which gives the same pairs.
  PartnerSearch(const GrowingKdTree& target, std::size_t source_size, double max_distance,
                unsigned threads = 1);

  /// Replaces `pairs` with each moved source point's closest target point within the bound, in source
  /// order. `moved` keeps its size between calls.
  void pair(const PointCloud& moved, std::vector<Correspondence>& pairs);

  /// Kd-tree searches so far (the rest were reused).
  [[nodiscard]] std::size_t searches() const { return searches_; }

 private:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  struct Partner {
    Eigen::Vector3d searched_at = Eigen::Vector3d::Zero();  ///< the point where it was last searched
    double reuse_squared =
        -1.0;  ///< squared distance it may move from there keeping `target`; < 0: unsearched
    std::size_t target = kNone;     ///< its closest target point within the search reach, if any
    std::size_t runner_up = kNone;  ///< the next closest: with `target`, bounds the next search
  };

  /// Searches the tree for the partners of `q`, the moved point of `partner`.
  void search(const Eigen::Vector3d& q, Partner& partner) const;

  const GrowingKdTree* target_;
  double max_squared_;
  double reach_;  ///< search bound: a little beyond max_distance, so points without a partner can skip too
  unsigned threads_;
  std::vector<Partner> partners_;
  std::vector<std::size_t> stale_;  ///< scratch: the points searched this pairing
  std::size_t searches_ = 0;
};

}  // namespace strata

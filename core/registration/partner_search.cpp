#include "core/registration/partner_search.hpp"

#include <cmath>

#include "core/parallel/parallel_for.hpp"

namespace strata {
namespace {

/// How much farther than the pairing bound a search looks: a point with no target point within the reach
/// keeps having no partner until it has moved this share of the bound.
constexpr double kReachMargin = 0.1;

/// Fewer searches than this a thread are left to the caller's: a search costs about half a microsecond, a
/// thread's start about 30.
constexpr std::size_t kMinSearchesPerThread = 256;

}  // namespace

PartnerSearch::PartnerSearch(const GrowingKdTree& target, std::size_t source_size, double max_distance,
                             unsigned threads)
    : target_(&target),
      max_squared_(max_distance * max_distance),
      reach_(max_distance * (1.0 + kReachMargin)),
      threads_(threads),
      partners_(source_size) {}

void PartnerSearch::search(const Eigen::Vector3d& q, Partner& partner) const {
  NearestTwo hint;
  if (partner.target != kNone)
    hint.first = Neighbor{partner.target, 0.0};
  if (partner.runner_up != kNone)
    hint.second = Neighbor{partner.runner_up, 0.0};
  const NearestTwo two = target_->nearest_two(q, reach_, hint);
  partner.searched_at = q;
  if (!two.first) {
    // Nothing within the reach: nothing within the bound until the point has moved the margin.
    partner.target = kNone;
    partner.runner_up = kNone;
    const double margin = reach_ - std::sqrt(max_squared_);
    partner.reuse_squared = margin * margin;
  } else {
    partner.target = two.first->index;
    partner.runner_up = two.second ? two.second->index : kNone;
    const double d1 = std::sqrt(two.first->squared_distance);
    const double d2 = two.second ? std::sqrt(two.second->squared_distance) : reach_;
    const double reuse = 0.5 * (d2 - d1);
    partner.reuse_squared = reuse * reuse;
  }
}

void PartnerSearch::pair(const PointCloud& moved, std::vector<Correspondence>& pairs) {
  // The points that moved too far to keep their partner, then their searches, split over the threads:
  // each search reads the tree and writes its own point's partner only.
  stale_.clear();
  for (std::size_t i = 0; i < moved.size(); ++i)
    if ((moved[i] - partners_[i].searched_at).squaredNorm() > partners_[i].reuse_squared)
      stale_.push_back(i);
  parallel_for(stale_.size(), threads_, kMinSearchesPerThread, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      search(moved[stale_[k]], partners_[stale_[k]]);
  });
  searches_ += stale_.size();
  pairs.clear();
  const PointCloud& points = target_->points();
  for (std::size_t i = 0; i < moved.size(); ++i) {
    const Partner& partner = partners_[i];
    if (partner.target != kNone && (moved[i] - points[partner.target]).squaredNorm() <= max_squared_)
      pairs.push_back({i, partner.target});
  }
}

}  // namespace strata

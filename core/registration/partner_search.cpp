#include "core/registration/partner_search.hpp"

#include <cmath>

namespace strata {
namespace {

/// How much farther than the pairing bound a search looks: a point with no target point within the reach
/// keeps having no partner until it has moved this share of the bound.
constexpr double kReachMargin = 0.1;

}  // namespace

PartnerSearch::PartnerSearch(const KdTree& target, std::size_t source_size, double max_distance)
    : target_(&target),
      max_squared_(max_distance * max_distance),
      reach_(max_distance * (1.0 + kReachMargin)),
      partners_(source_size) {}

void PartnerSearch::pair(const PointCloud& moved, std::vector<Correspondence>& pairs) {
  pairs.clear();
  const PointCloud& points = target_->points();
  for (std::size_t i = 0; i < moved.size(); ++i) {
    Partner& partner = partners_[i];
    const Eigen::Vector3d& q = moved[i];
    if ((q - partner.searched_at).squaredNorm() > partner.reuse_squared) {
      NearestTwo hint;
      if (partner.target != kNone)
        hint.first = Neighbor{partner.target, 0.0};
      if (partner.runner_up != kNone)
        hint.second = Neighbor{partner.runner_up, 0.0};
      const NearestTwo two = target_->nearest_two(q, reach_, hint);
      ++searches_;
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
    if (partner.target != kNone && (q - points[partner.target]).squaredNorm() <= max_squared_)
      pairs.push_back({i, partner.target});
  }
}

}  // namespace strata

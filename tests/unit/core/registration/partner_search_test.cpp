#include "core/registration/partner_search.hpp"

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <random>

#include "core/ann/kdtree.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

// Reusing partners is exact: over a sequence of small and large moves, as ICP makes them, every pairing
// is as close as a fresh search's (equidistant points may differ), and some searches were saved.
TEST(PartnerSearch, PairsAsAFullSearchWouldWhileSkippingSearches) {
  const PointCloud target = test::room_scene(0.1, 0.01, 1);
  const PointCloud source = test::room_scene(0.4, 0.02, 2);
  const GrowingKdTree tree(target);
  const double bound = 0.25;
  PartnerSearch partners(tree, source.size(), bound);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise;
  Eigen::Isometry3d transform = test::make_transform(0.3, -0.2, 0.05, 0.02, 0.01, 0.1);
  std::vector<Correspondence> pairs;
  std::size_t calls = 0;
  for (int iteration = 0; iteration < 30; ++iteration) {
    // Steps that shrink like ICP's, from decimetres to tenths of a millimetre.
    const double size = 0.1 * std::pow(0.75, iteration);
    transform = test::make_transform(size * noise(rng), size * noise(rng), size * noise(rng),
                                     0.1 * size * noise(rng), 0.1 * size * noise(rng), size * noise(rng)) *
                transform;
    const PointCloud moved = transformed(source, transform);
    partners.pair(moved, pairs);
    calls += moved.size();
    std::size_t k = 0;
    for (std::size_t i = 0; i < moved.size(); ++i) {
      // A fresh search is the reference (the tree itself is checked against brute force below and in
      // nearest_neighbor_test.cpp; brute force here would take minutes under the sanitizers).
      const std::optional<Neighbor> expected = tree.nearest(moved[i], bound);
      if (!expected)
        continue;
      ASSERT_LT(k, pairs.size());
      ASSERT_EQ(pairs[k].source, i) << "iteration " << iteration;
      EXPECT_NEAR((moved[i] - target[pairs[k].target]).squaredNorm(), expected->squared_distance, 1e-12);
      ++k;
    }
    EXPECT_EQ(k, pairs.size()) << "iteration " << iteration;
  }
  EXPECT_LT(partners.searches(), calls / 2);
}

TEST(KdTree, NearestTwoAreTheTwoClosestWithinTheBound) {
  const PointCloud target = test::room_scene(0.1, 0.01, 4);
  const KdTree tree(target);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 6.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q(uniform(rng), uniform(rng), 0.5 * uniform(rng));
    std::array<double, 2> all = {
        std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity()};  // the two smallest, by brute force
    for (const Eigen::Vector3d& p : target) {
      const double d = (p - q).squaredNorm();
      if (d < all[1])
        all = d < all[0] ? std::array<double, 2>{d, all[0]} : std::array<double, 2>{all[0], d};
    }
    const NearestTwo two = tree.nearest_two(q, 0.3);
    ASSERT_EQ(two.first.has_value(), all[0] <= 0.09);
    ASSERT_EQ(two.second.has_value(), all[1] <= 0.09);
    if (two.first) {
      EXPECT_DOUBLE_EQ(two.first->squared_distance, all[0]);
    }
    if (two.second) {
      EXPECT_DOUBLE_EQ(two.second->squared_distance, all[1]);
    }
    // A hint (any two points) changes nothing but where the search starts.
    const NearestTwo hinted = tree.nearest_two(q, 0.3, {Neighbor{7, 0.0}, Neighbor{8, 0.0}});
    ASSERT_EQ(hinted.first.has_value(), two.first.has_value());
    if (two.first) {
      EXPECT_DOUBLE_EQ(hinted.first->squared_distance, two.first->squared_distance);
    }
    if (two.second) {
      EXPECT_DOUBLE_EQ(hinted.second->squared_distance, two.second->squared_distance);
    }
  }
}

}  // namespace
}  // namespace strata

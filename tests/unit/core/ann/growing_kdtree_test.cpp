#include "core/ann/growing_kdtree.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/ann/kdtree.hpp"

namespace strata {
namespace {

PointCloud random_cloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  PointCloud points;
  for (std::size_t i = 0; i < n; ++i)
    points.emplace_back(coordinate(rng), coordinate(rng), 0.2 * coordinate(rng));
  return points;
}

// Grown in pieces (a small tree for the recent points, full builds in between), it answers every query as
// one kd-tree over the whole cloud does, with the same indices.
TEST(GrowingKdTree, AnswersAsOneTreeOverTheWholeCloud) {
  const PointCloud all = random_cloud(6000, 1);
  const PointCloud queries = random_cloud(300, 2);
  GrowingKdTree growing(PointCloud(all.begin(), all.begin() + 2000));
  std::size_t size = 2000;
  for (const std::size_t piece : {100, 250, 30, 1500, 120, 2000}) {
    growing.append(std::span(all).subspan(size, piece));
    size += piece;
    const KdTree whole(PointCloud(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(size)));
    ASSERT_EQ(growing.size(), size);
    std::vector<Neighbor> expected;
    std::vector<Neighbor> found;
    for (const Eigen::Vector3d& q : queries) {
      const std::optional<Neighbor> one = whole.nearest(q, 0.4);
      const std::optional<Neighbor> grown = growing.nearest(q, 0.4);
      ASSERT_EQ(one.has_value(), grown.has_value());
      if (one) {
        EXPECT_EQ(one->index, grown->index);
      }
      const NearestTwo two = whole.nearest_two(q, 0.4);
      // A hint from the other end of the cloud (the recent tree's or the main one's) changes nothing.
      const NearestTwo grown_two = growing.nearest_two(q, 0.4, {Neighbor{size - 1, 0.0}, Neighbor{0, 0.0}});
      ASSERT_EQ(two.first.has_value(), grown_two.first.has_value());
      ASSERT_EQ(two.second.has_value(), grown_two.second.has_value());
      if (two.first) {
        EXPECT_EQ(two.first->index, grown_two.first->index);
      }
      if (two.second) {
        EXPECT_EQ(two.second->index, grown_two.second->index);
      }
      whole.k_nearest(q, 20, expected);
      growing.k_nearest(q, 20, found);
      ASSERT_EQ(expected.size(), found.size());
      for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(expected[i].index, found[i].index);
    }
  }
  // 2000 points, then +100 +250 (12.5 % recent), +30, +1500 (over a quarter: full), +120, +2000 (full).
  EXPECT_EQ(growing.full_builds(), 3U);
}

}  // namespace
}  // namespace strata

#include <gtest/gtest.h>

#include <random>

#include "core/ann/brute_force.hpp"
#include "core/ann/growing_kdtree.hpp"
#include "core/ann/kdtree.hpp"
#include "core/ann/voxel_hash_map.hpp"

namespace strata {
namespace {

PointCloud random_cloud(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-5.0, 5.0);
  PointCloud cloud;
  for (std::size_t i = 0; i < count; ++i)
    cloud.emplace_back(uniform(rng), uniform(rng), uniform(rng) * 0.3);
  return cloud;
}

TEST(NearestNeighbor, KdTreeAndVoxelHashAgreeWithBruteForce) {
  const PointCloud target = random_cloud(5000, 1);
  const PointCloud queries = random_cloud(700, 2);  // about 1,500 hits over the three bounds
  const KdTree tree(target);
  const VoxelHashMap hash(target, 0.3);
  std::size_t found = 0;
  for (const double bound : {0.1, 0.25, 1.0}) {
    for (const Eigen::Vector3d& q : queries) {
      const std::optional<Neighbor> expected = brute_force_nearest(target, q, bound);
      const std::optional<Neighbor> by_tree = tree.nearest(q, bound);
      const std::optional<Neighbor> by_hash = hash.nearest(q, bound);
      ASSERT_EQ(expected.has_value(), by_tree.has_value());
      ASSERT_EQ(expected.has_value(), by_hash.has_value());
      if (!expected)
        continue;
      ++found;
      // Indices may differ only between equidistant points; distances may not.
      EXPECT_DOUBLE_EQ(by_tree->squared_distance, expected->squared_distance);
      EXPECT_DOUBLE_EQ(by_hash->squared_distance, expected->squared_distance);
      EXPECT_EQ(tree.points()[by_tree->index], target[expected->index]);
      EXPECT_EQ(hash.points()[by_hash->index], target[expected->index]);
    }
  }
  EXPECT_GT(found, 1000U);  // the comparison covered real hits, not only misses
}

TEST(NearestNeighbor, BoundExcludesFartherPoints) {
  const KdTree tree(PointCloud{{0, 0, 0}, {1, 0, 0}});
  EXPECT_FALSE(tree.nearest({0.5, 0.4, 0}, 0.5).has_value());
  const std::optional<Neighbor> hit = tree.nearest({0.9, 0, 0}, 0.5);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->index, 1U);
  EXPECT_NEAR(hit->squared_distance, 0.01, 1e-12);
}

TEST(NearestNeighbor, KNearestAreSortedAndExact) {
  const PointCloud target = random_cloud(1000, 3);
  const KdTree tree(target);
  const Eigen::Vector3d q(0.1, 0.2, 0.0);
  const std::vector<Neighbor> neighbors = tree.k_nearest(q, 8);
  ASSERT_EQ(neighbors.size(), 8U);
  std::vector<double> all;
  for (const Eigen::Vector3d& p : target)
    all.push_back((p - q).squaredNorm());
  std::sort(all.begin(), all.end());
  for (std::size_t i = 0; i < neighbors.size(); ++i)
    EXPECT_DOUBLE_EQ(neighbors[i].squared_distance, all[i]);
}

TEST(NearestNeighbor, EmptyTreeFindsNothingAndMovedTreeStillWorks) {
  const KdTree empty{PointCloud{}};
  EXPECT_FALSE(empty.nearest({0, 0, 0}, 10.0).has_value());
  EXPECT_TRUE(empty.k_nearest({0, 0, 0}, 3).empty());
  KdTree original(PointCloud{{1, 2, 3}});
  const KdTree moved(std::move(original));
  ASSERT_TRUE(moved.nearest({1, 2, 3.1}, 1.0).has_value());
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
      for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_DOUBLE_EQ(expected[i].squared_distance, found[i].squared_distance);
        // Points equally far may come in either order (the compilers differ); any other must not.
        const bool tied =
            (i > 0 && expected[i - 1].squared_distance == expected[i].squared_distance) ||
            (i + 1 < expected.size() && expected[i + 1].squared_distance == expected[i].squared_distance);
        if (!tied) {
          EXPECT_EQ(expected[i].index, found[i].index);
        }
      }
    }
  }
  // 2000 points, then +100 +250 (12.5 % recent), +30, +1500 (over a quarter: full), +120, +2000 (full).
  EXPECT_EQ(growing.full_builds(), 3U);
}

}  // namespace
}  // namespace strata

#include <gtest/gtest.h>

#include <random>

#include "core/ann/brute_force.hpp"
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
  const PointCloud queries = random_cloud(2000, 2);
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

}  // namespace
}  // namespace strata

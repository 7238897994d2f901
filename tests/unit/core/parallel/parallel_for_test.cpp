// The registration's work on several threads: the same result as on one, item for item. In the TSan
// preset too (tests/CMakeLists.txt), which checks that the threads write apart.
#include "core/parallel/parallel_for.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <vector>

#include "core/ann/kdtree.hpp"
#include "core/registration/icp.hpp"
#include "core/registration/normals.hpp"
#include "core/registration/partner_search.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

TEST(ParallelFor, CoversEachItemOnceInAtMostTheThreadsAsked) {
  for (const std::size_t count : {0UL, 1UL, 99UL, 100UL, 1001UL}) {
    std::vector<int> hits(count, 0);
    std::atomic<int> parts = 0;
    parallel_for(count, 3, 100, [&](std::size_t begin, std::size_t end) {
      ++parts;
      for (std::size_t i = begin; i < end; ++i)
        ++hits[i];
    });
    for (std::size_t i = 0; i < count; ++i)
      ASSERT_EQ(hits[i], 1) << "item " << i << " of " << count;
    // One part for fewer than two parts' worth; three at most.
    EXPECT_EQ(parts.load(), count < 200 ? 1 : 3) << count << " items";
  }
}

// Normals estimated ahead on two threads, duplicates among the indices, are the ones at() estimates one
// by one, bit for bit.
TEST(LazyNormals, EstimatedOnThreadsAsOneByOne) {
  const GrowingKdTree tree(test::room_scene(0.1, 0.01, 1));
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i < tree.size(); i += 3)
    indices.push_back(i);
  indices.insert(indices.end(), indices.begin(), indices.begin() + 100);
  ASSERT_GT(indices.size(), 1000U) << "enough for two threads";
  LazyNormals ahead(tree);
  ahead.estimate(indices, 2);
  LazyNormals one_by_one(tree);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < tree.size(); ++i) {
    const Eigen::Vector3d* expected = one_by_one.at(i);
    const Eigen::Vector3d* got = ahead.at(i);
    ASSERT_EQ(expected == nullptr, got == nullptr) << "point " << i;
    if (expected != nullptr) {
      EXPECT_EQ(*expected, *got) << "point " << i;
      ++valid;
    }
  }
  EXPECT_GT(valid, tree.size() / 2) << "a room is mostly surfaces";
}

// Pairing on two threads gives the pairs of one, and searches as often.
TEST(PartnerSearch, PairsOnTwoThreadsAsOnOne) {
  const GrowingKdTree tree(test::room_scene(0.1, 0.01, 1));
  const PointCloud source = test::room_scene(0.15, 0.02, 2);
  ASSERT_GT(source.size(), 1000U) << "enough for two threads";
  PartnerSearch one(tree, source.size(), 0.25, 1);
  PartnerSearch two(tree, source.size(), 0.25, 2);
  std::vector<Correspondence> pairs_one;
  std::vector<Correspondence> pairs_two;
  for (int iteration = 0; iteration < 10; ++iteration) {
    const double size = 0.1 * std::pow(0.5, iteration);
    const PointCloud moved =
        transformed(source, test::make_transform(size, -size, 0.5 * size, 0.0, 0.0, size));
    one.pair(moved, pairs_one);
    two.pair(moved, pairs_two);
    ASSERT_EQ(pairs_one.size(), pairs_two.size()) << "iteration " << iteration;
    for (std::size_t k = 0; k < pairs_one.size(); ++k) {
      ASSERT_EQ(pairs_one[k].source, pairs_two[k].source);
      ASSERT_EQ(pairs_one[k].target, pairs_two[k].target);
    }
  }
  EXPECT_EQ(one.searches(), two.searches());
}

// A point-to-plane registration on two threads lands where it does on one, to the last bit.
TEST(Icp, RegistersOnTwoThreadsAsOnOne) {
  const GrowingKdTree tree(test::room_scene(0.1, 0.01, 1));
  const PointCloud source = test::room_scene(0.15, 0.02, 2);
  IcpOptions options;
  options.metric = IcpMetric::kPointToPlane;
  options.max_correspondence_distance = 0.5;
  const Eigen::Isometry3d guess = test::make_transform(0.2, -0.1, 0.05, 0.01, -0.01, 0.05);
  LazyNormals normals_one(tree);
  const IcpResult one = align(source, tree, &normals_one, guess, options);
  options.threads = 2;
  LazyNormals normals_two(tree);
  const IcpResult two = align(source, tree, &normals_two, guess, options);
  EXPECT_EQ(one.transform.matrix(), two.transform.matrix());
  EXPECT_EQ(one.iterations, two.iterations);
  EXPECT_EQ(one.pairs.size(), two.pairs.size());
  EXPECT_LT(two.transform.translation().norm(), 0.01) << "and it did register";
}

}  // namespace
}  // namespace strata

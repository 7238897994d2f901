#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>
#include <tuple>

#include "core/points/voxel_downsample.hpp"
#include "core/points/voxel_key.hpp"
#include "core/points/voxel_key_map.hpp"
#include "core/points/voxel_key_set.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

TEST(VoxelDownsample, KeepsOneMeasuredPointPerVoxel) {
  const PointCloud cloud = test::room_scene(0.02);
  const double voxel = 0.2;
  const PointCloud kept = voxel_downsample(cloud, voxel);
  ASSERT_LT(kept.size(), cloud.size() / 10);
  std::set<VoxelKey> cells;
  for (const Eigen::Vector3d& p : kept)
    EXPECT_TRUE(cells.insert(voxel_key(voxel_cell(p, 1.0 / voxel))).second) << "two points in one voxel";
  // Every input voxel is still represented.
  for (const Eigen::Vector3d& p : cloud)
    EXPECT_TRUE(cells.contains(voxel_key(voxel_cell(p, 1.0 / voxel))));
  // The kept points are input points, not averages.
  EXPECT_EQ(kept.front(), cloud.front());
}

TEST(VoxelDownsample, NegativeCoordinatesFallIntoTheirOwnVoxel) {
  // floor(), not truncation: -0.05 and +0.05 are in different 0.1 m voxels.
  const PointCloud kept = voxel_downsample({{-0.05, 0, 0}, {0.05, 0, 0}, {0.07, 0, 0}}, 0.1);
  EXPECT_EQ(kept.size(), 2U);
}

TEST(VoxelDownsample, NonPositiveVoxelKeepsEverything) {
  const PointCloud cloud{{0, 0, 0}, {0, 0, 0}};
  EXPECT_EQ(voxel_downsample(cloud, 0.0).size(), 2U);
}

TEST(VoxelDownsample, WithAMinimumRangeIsCropThenThin) {
  const PointCloud cloud = test::room_scene(0.02);
  for (const double min_range : {0.0, 0.5, 2.0}) {
    PointCloud cropped;
    for (const auto& point : cloud)
      if (point.norm() >= min_range)
        cropped.push_back(point);
    EXPECT_EQ(voxel_downsample(cloud, 0.2, min_range), voxel_downsample(cropped, 0.2)) << min_range;
  }
}

TEST(VoxelKeyMap, FindsWhatWasStoredThroughGrowth) {
  VoxelKeyMap map(2);  // small: grows many times
  for (std::uint32_t i = 0; i < 5000; ++i) {
    const auto [value, added] =
        map.try_emplace(voxel_key({static_cast<int>(i % 71), -static_cast<int>(i), 3}), i);
    EXPECT_TRUE(added);
    EXPECT_EQ(value, i);
  }
  EXPECT_EQ(map.size(), 5000U);
  const auto [value, added] = map.try_emplace(voxel_key({5, -5, 3}), 99);
  EXPECT_FALSE(added);
  EXPECT_EQ(value, 5U);
  ASSERT_NE(map.find(voxel_key({4999 % 71, -4999, 3})), nullptr);
  EXPECT_EQ(*map.find(voxel_key({4999 % 71, -4999, 3})), 4999U);
  EXPECT_EQ(map.find(voxel_key({0, 1, 3})), nullptr);
  map.clear();
  EXPECT_EQ(map.size(), 0U);
  EXPECT_EQ(map.find(voxel_key({5, -5, 3})), nullptr);
}

TEST(VoxelKeySet, KnowsWhatWasInsertedThroughGrowth) {
  VoxelKeySet set(2);  // small: grows many times
  for (int i = 0; i < 5000; ++i)
    EXPECT_TRUE(set.insert(voxel_key({i % 71, -i, 3})));
  EXPECT_EQ(set.size(), 5000U);
  for (int i = 0; i < 5000; ++i)
    EXPECT_FALSE(set.insert(voxel_key({i % 71, -i, 3})));
  EXPECT_TRUE(set.insert(voxel_key({0, 1, 3})));
  EXPECT_EQ(set.size(), 5001U);
}

// A scan whose points nearly all fall into voxels of their own (sparse rings) grows the set on the way:
// still the first point of each voxel, in scan order.
TEST(VoxelDownsample, ASparseScanKeepsNearlyEveryPointInOrder) {
  PointCloud cloud;
  for (int i = 0; i < 3000; ++i)
    cloud.emplace_back(0.3 * i + 0.01, 0.05, 0.05);
  cloud.emplace_back(0.02, 0.06, 0.04);  // shares the first voxel
  const PointCloud kept = voxel_downsample(cloud, 0.1);
  ASSERT_EQ(kept.size(), 3000U);
  EXPECT_TRUE(std::equal(kept.begin(), kept.end(), cloud.begin()));
}

}  // namespace
}  // namespace strata

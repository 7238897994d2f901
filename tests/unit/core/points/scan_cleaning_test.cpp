#include "core/points/scan_cleaning.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace strata {
namespace {

TEST(ScanCleaning, KeepsTheMeasurementsInTheBaseFrame) {
  Eigen::Isometry3d sensor_to_base = Eigen::Isometry3d::Identity();
  sensor_to_base.translation() = Eigen::Vector3d(0.2, 0, 1.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> scan = {
      {2, 0, 0},       // kept
      {0.1f, 0, 0},    // the robot itself: too close
      {8.1f, 0, 0},    // a max-range "no return"
      {8.095f, 0, 0},  // noise just under it: a "no return" too
      {nan, 0, 0},     // invalid
      {0, 3, -1},      // kept
      {std::numeric_limits<float>::infinity(), 0, 0},
  };
  const PointCloud points = clean_scan(scan, sensor_to_base, {.min_range = 0.3, .no_return_range = 8.1});
  ASSERT_EQ(points.size(), 2u);
  EXPECT_TRUE(points[0].isApprox(Eigen::Vector3d(2.2, 0, 1.0)));
  EXPECT_TRUE(points[1].isApprox(Eigen::Vector3d(0.2, 3, 0.0)));
}

TEST(ScanCleaning, ThePointsTimesAreKeptWithThePointsKept) {
  const std::vector<Eigen::Vector3f> scan = {{2, 0, 0}, {0.1f, 0, 0}, {0, 3, 0}};
  std::vector<float> times = {-0.09f, -0.05f, -0.01f};
  std::vector<float> kept;
  EXPECT_EQ(clean_scan(scan, Eigen::Isometry3d::Identity(), {}, times, &kept).size(), 2u);
  EXPECT_EQ(kept, (std::vector<float>{-0.09f, -0.01f}));
  times.pop_back();  // not one per point: unknown
  EXPECT_EQ(clean_scan(scan, Eigen::Isometry3d::Identity(), {}, times, &kept).size(), 2u);
  EXPECT_TRUE(kept.empty());
}

TEST(ScanCleaning, SensorsWithoutNoReturnReadingsKeepFarPoints) {
  const std::vector<Eigen::Vector3f> scan = {{80, 0, 0}};
  EXPECT_EQ(clean_scan(scan, Eigen::Isometry3d::Identity(), {.no_return_range = 0.0}).size(), 1u);
}

}  // namespace
}  // namespace strata

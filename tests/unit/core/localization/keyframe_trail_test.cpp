#include "core/localization/keyframe_trail.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

Eigen::Isometry3d along_x(double x) {
  return Eigen::Isometry3d(Eigen::Translation3d(x, 0.0, 0.0));
}

// The scans between two keyframes go into the second, in its base frame, each with its own ray origin and
// ground, oldest first; a voxel an earlier scan reached is not kept again.
TEST(KeyframeTrail, TheNextKeyframeKeepsTheScansSinceThePreviousInItsFrame) {
  KeyframeTrail trail(0.1);
  const Eigen::Vector3d sensor(0.0, 0.0, 1.0);
  // Previous keyframe at x = 0; a scan from x = 0.5 sees a post at x = 2.05 (map frame).
  trail.add({{1.55, 0.0, 0.0}}, sensor, along_x(0.5));
  EXPECT_EQ(trail.size(), 1U);
  // The new keyframe at x = 1.0 sees the same post and a wall at x = 3.05.
  const std::vector<KeyframeScan> scans =
      trail.close({{1.06, 0.0, 0.0}, {2.05, 0.0, 0.0}}, sensor, along_x(1.0));
  EXPECT_EQ(trail.size(), 0U);
  ASSERT_EQ(scans.size(), 2U);
  ASSERT_EQ(scans[0].points.size(), 1U);
  EXPECT_TRUE(scans[0].points[0].isApprox(Eigen::Vector3f(1.05F, 0.0F, 0.0F)));
  EXPECT_TRUE(scans[0].ground.isApprox(Eigen::Vector3f(-0.5F, 0.0F, 0.0F)));
  EXPECT_TRUE(scans[0].sensor_origin.isApprox(Eigen::Vector3f(-0.5F, 0.0F, 1.0F)));
  ASSERT_EQ(scans[1].points.size(), 1U) << "the post is the trail's: only the wall is new";
  EXPECT_TRUE(scans[1].points[0].isApprox(Eigen::Vector3f(2.05F, 0.0F, 0.0F)));
  EXPECT_TRUE(scans[1].ground.isZero());
  EXPECT_TRUE(scans[1].sensor_origin.isApprox(sensor.cast<float>()));
}

// A keyframe every scan (a fast lidar): its own thinned scan, as it is.
TEST(KeyframeTrail, AKeyframeWithoutATrailKeepsItsOwnThinnedScan) {
  KeyframeTrail trail(0.1);
  const Eigen::Vector3d sensor(0.0, 0.0, 1.0);
  const PointCloud thinned = trail.thin({{1.01, 0.0, 0.0}, {1.02, 0.0, 0.0}, {2.05, 0.0, 0.0}});
  ASSERT_EQ(thinned.size(), 2U) << "one point per 0.1 m voxel, the first";
  const std::vector<KeyframeScan> scans = trail.close(thinned, sensor, along_x(1.0));
  ASSERT_EQ(scans.size(), 1U);
  ASSERT_EQ(scans[0].points.size(), 2U);
  EXPECT_TRUE(scans[0].points[0].isApprox(Eigen::Vector3f(1.01F, 0.0F, 0.0F)));
  EXPECT_TRUE(scans[0].points[1].isApprox(Eigen::Vector3f(2.05F, 0.0F, 0.0F)));
  EXPECT_TRUE(scans[0].ground.isZero());
  EXPECT_TRUE(scans[0].sensor_origin.isApprox(sensor.cast<float>()));
}

TEST(KeyframeTrail, WithoutAVoxelNothingIsKept) {
  KeyframeTrail trail(0.0);
  trail.add({{1.0, 0.0, 0.0}}, Eigen::Vector3d::Zero(), along_x(0.5));
  EXPECT_EQ(trail.size(), 0U);
  EXPECT_TRUE(trail.close({{1.0, 0.0, 0.0}}, Eigen::Vector3d::Zero(), along_x(1.0)).empty());
}

}  // namespace
}  // namespace strata

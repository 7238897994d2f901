#include "core/points/deskew.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace strata {
namespace {

Eigen::Isometry3d planar(const Pose2& pose) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  transform.translation() = Eigen::Vector3d(pose.x, pose.y, 0.0);
  return transform;
}

TEST(Deskew, ABaseDrivingAnArcIsWhereTheArcTakesIt) {
  // A quarter circle of radius 2 m: 1 m/s forward turning at 0.5 rad/s for pi seconds.
  const Pose2 end = pose_after({1.0, 0.0, 0.5}, std::numbers::pi);
  EXPECT_NEAR(end.x, 2.0, 1e-9);
  EXPECT_NEAR(end.y, 2.0, 1e-9);
  EXPECT_NEAR(end.theta, std::numbers::pi / 2.0, 1e-12);
  const Pose2 straight = pose_after({2.0, -1.0, 0.0}, -0.5);  // where it was half a second ago
  EXPECT_NEAR(straight.x, -1.0, 1e-12);
  EXPECT_NEAR(straight.y, 0.5, 1e-12);
}

TEST(Deskew, PointsMeasuredAlongTheWayLandWhereTheEndPoseSeesThem) {
  // A base driving 2 m/s while turning 1 rad/s measures fixed points of the world over 0.1 s, each in the
  // frame it has at that instant; deskewed, each is where the base at the end sees it.
  const Pose2 velocity{2.0, 0.3, 1.0};
  const Eigen::Isometry3d end_in_world = planar({5.0, -1.0, 0.4});
  PointCloud measured;
  PointCloud expected;
  std::vector<float> times;
  for (int i = 0; i < 100; ++i) {
    const float time = -0.1f + 0.001f * static_cast<float>(i);
    const Eigen::Isometry3d then_in_world =
        end_in_world * planar(pose_after(velocity, static_cast<double>(time)));
    const Eigen::Vector3d world_point(10.0 * std::cos(0.06 * i), 10.0 * std::sin(0.06 * i), 0.1 * i - 2.0);
    measured.push_back(then_in_world.inverse() * world_point);
    expected.push_back(end_in_world.inverse() * world_point);
    times.push_back(time);
  }
  PointCloud deskewed = measured;
  deskew(deskewed, times, velocity);
  double largest_smear = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    EXPECT_NEAR((deskewed[i] - expected[i]).norm(), 0.0, 1e-5) << i;
    largest_smear = std::max(largest_smear, (measured[i] - expected[i]).norm());
  }
  EXPECT_GT(largest_smear, 0.5);  // what there was to undo
}

TEST(Deskew, WithoutTimesOrMotionThePointsStay) {
  const PointCloud original{{1, 2, 3}, {4, 5, 6}};
  PointCloud points = original;
  deskew(points, {}, {1.0, 0.0, 1.0});
  EXPECT_EQ(points, original);
  const std::vector<float> times{-0.05f, 0.0f};
  deskew(points, times, {});
  EXPECT_EQ(points, original);
}

TEST(Deskew, APointWithoutATimeStaysAndAMismatchIsRefused) {
  PointCloud points{{1, 0, 0}, {1, 0, 0}};
  const std::vector<float> times{std::numeric_limits<float>::quiet_NaN(), -0.1f};
  deskew(points, times, {1.0, 0.0, 0.0});
  EXPECT_TRUE(points[0].isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_NEAR(points[1].x(), 0.9, 1e-6);  // measured 0.1 m back
  const std::vector<float> one{-0.1f};
  EXPECT_THROW(deskew(points, one, {1.0, 0.0, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace strata

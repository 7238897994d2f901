#include "core/geometry/pose.hpp"

#include <gtest/gtest.h>

#include "core/geometry/angles.hpp"

namespace strata {
namespace {

TEST(Pose2, ComposeThenRelativeIsIdentity) {
  const Pose2 start{1.0, -2.0, 0.7};
  const Pose2 delta{0.5, 0.25, -1.1};
  const Pose2 end = start.compose(delta);
  const Pose2 back = end.relative_to(start);
  EXPECT_NEAR(back.x, delta.x, 1e-12);
  EXPECT_NEAR(back.y, delta.y, 1e-12);
  EXPECT_NEAR(back.theta, delta.theta, 1e-12);
}

TEST(Pose2, ComposeMovesAlongTheHeading) {
  const Pose2 facing_north{0.0, 0.0, kPi / 2};
  const Pose2 moved = facing_north.compose({1.0, 0.0, 0.0});
  EXPECT_NEAR(moved.x, 0.0, 1e-12);
  EXPECT_NEAR(moved.y, 1.0, 1e-12);
}

TEST(Pose3, IsometryRoundTripRecoversAngles) {
  Pose3 pose;
  pose.position = {1.0, 2.0, 3.0};
  pose.roll = 0.1;
  pose.pitch = -0.3;
  pose.yaw = 2.5;
  const Pose3 back = Pose3::from_isometry(pose.to_isometry());
  EXPECT_TRUE(back.position.isApprox(pose.position));
  EXPECT_NEAR(back.roll, pose.roll, 1e-12);
  EXPECT_NEAR(back.pitch, pose.pitch, 1e-12);
  EXPECT_NEAR(back.yaw, pose.yaw, 1e-12);
}

TEST(Pose3, AnglesFollowTheZyxConvention) {
  // Pitch up by 90 degrees about y turns the robot's x axis onto -z (R = Rz Ry Rx).
  Pose3 pose;
  pose.pitch = kPi / 2;
  const Eigen::Vector3d forward = pose.to_isometry().linear() * Eigen::Vector3d::UnitX();
  EXPECT_TRUE(forward.isApprox(Eigen::Vector3d(0, 0, -1), 1e-12));
}

TEST(Pose3, GimbalLockKeepsTheSameRotation) {
  for (const double pitch : {kPi / 2, -kPi / 2}) {
    Pose3 pose;
    pose.pitch = pitch;
    pose.roll = 0.4;
    pose.yaw = -0.9;
    const Eigen::Isometry3d original = pose.to_isometry();
    const Pose3 back = Pose3::from_isometry(original);
    EXPECT_TRUE(back.to_isometry().linear().isApprox(original.linear(), 1e-9)) << "pitch " << pitch;
  }
}

}  // namespace
}  // namespace strata

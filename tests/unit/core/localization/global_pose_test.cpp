#include "core/localization/global_pose.hpp"

#include <gtest/gtest.h>

#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

TEST(GlobalPose, NoCorrectionIsOdometry) {
  const GlobalPose global;
  const Pose3 pose = global.pose({1.0, 2.0, 0.5});
  EXPECT_TRUE(pose.position.isApprox(Eigen::Vector3d(1, 2, 0)));
  EXPECT_NEAR(pose.yaw, 0.5, 1e-12);
}

TEST(GlobalPose, CorrectionsAccumulateLeftToRight) {
  // Thesis eqs. 4.13-4.14: Rg <- R Rg, tg <- R tg + t; the total is the later correction after the earlier.
  const Eigen::Isometry3d first = test::make_transform(0.2, 0.0, 0.1, 0.0, 0.05, 0.1);
  const Eigen::Isometry3d second = test::make_transform(-0.1, 0.3, 0.0, 0.02, 0.0, -0.3);
  GlobalPose global;
  global.apply_correction(first);
  global.apply_correction(second);
  EXPECT_TRUE(global.correction().isApprox(second * first, 1e-12));
  EXPECT_FALSE(global.correction().isApprox(first * second, 1e-3));
}

TEST(GlobalPose, PositionIsTheCorrectedOdometryPoint) {
  // eq. 4.16: p = Rg (x_odom, y_odom, 0) + tg; roll and pitch come only from the correction.
  GlobalPose global;
  const Eigen::Isometry3d correction = test::make_transform(0.5, -0.2, 0.3, 0.0, 0.1, 0.2);
  global.apply_correction(correction);
  const Pose2 odometry{3.0, 1.0, 0.4};
  const Pose3 pose = global.pose(odometry);
  EXPECT_TRUE(pose.position.isApprox(correction * Eigen::Vector3d(3.0, 1.0, 0.0), 1e-12));
  const Eigen::Isometry3d expected = correction * test::make_transform(3.0, 1.0, 0.0, 0.0, 0.0, 0.4);
  EXPECT_TRUE(pose.to_isometry().isApprox(expected, 1e-9));
  EXPECT_GT(std::abs(pose.pitch), 0.05);
}

}  // namespace
}  // namespace strata

#include "core/localization/constant_velocity.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace strata {
namespace {

Eigen::Isometry3d planar(double x, double y, double theta) {
  return Pose3::from_pose2({x, y, theta}).to_isometry();
}

TEST(ConstantVelocityPrediction, BeforeAVelocityItPredictsNoMotionAndAllowsForTheFastestBase) {
  ConstantVelocityPrediction motion({.max_speed = 20.0, .max_turn_rate = 2.0});
  EXPECT_EQ(motion.predict(5.0).x, 0.0);
  motion.update(5.0, {}, planar(3.0, 1.0, 0.5), false, false);  // the first scan: nothing to register onto
  const Pose2 predicted = motion.predict(5.1);
  EXPECT_EQ(predicted.x, 0.0);
  EXPECT_EQ(predicted.theta, 0.0);
  EXPECT_FALSE(motion.knows_velocity());
  EXPECT_FALSE(motion.predict_pose(5.1));
  const GuessUncertainty uncertainty = motion.uncertainty(5.1);
  EXPECT_NEAR(uncertainty.translation, 2.0, 1e-9);
  EXPECT_NEAR(uncertainty.rotation, 0.2, 1e-9);
}

TEST(ConstantVelocityPrediction, TheMotionBetweenTwoScansIsCarriedOnPerSecond) {
  ConstantVelocityPrediction motion;
  // A car at 12 m/s turning 0.5 rad/s, scans 0.1 s apart; the map frame is turned against the odometry's.
  motion.update(10.0, {}, planar(3.0, 1.0, 0.5), false, false);
  const Eigen::Isometry3d second = planar(3.0, 1.0, 0.5) * planar(1.2, 0.0, 0.05);
  motion.update(10.1, {}, second, true, false);
  EXPECT_TRUE(motion.knows_velocity());
  // 0.2 s later (a scan was dropped): twice the motion, in the base's frame.
  const Pose2 predicted = motion.predict(10.3);
  EXPECT_NEAR(predicted.x, 2.4, 1e-9);
  EXPECT_NEAR(predicted.y, 0.0, 1e-9);
  EXPECT_NEAR(predicted.theta, 0.1, 1e-9);
  // The same in the frame of the poses: the second guess for a scan whose odometry is in doubt.
  ASSERT_TRUE(motion.predict_pose(10.3));
  EXPECT_TRUE(motion.predict_pose(10.3)->isApprox(second * planar(2.4, 0.0, 0.1), 1e-9));
  // The next scan predicted there and found there: the prediction goes on from it.
  motion.update(10.3, predicted, second * planar(2.4, 0.0, 0.1), true, false);
  const Pose2 next = motion.predict(10.4);
  EXPECT_NEAR(next.x, 2.4 + 1.2 * std::cos(0.1), 1e-9);
  EXPECT_NEAR(next.theta, 0.15, 1e-9);
}

TEST(ConstantVelocityPrediction, ARejectedMatchOrAMovedMapSaysNothingOfTheVelocity) {
  ConstantVelocityPrediction motion;
  motion.update(0.0, {}, planar(0.0, 0.0, 0.0), false, false);
  motion.update(0.1, {}, planar(1.0, 0.0, 0.0), false, false);  // rejected: the pose is the guess
  EXPECT_FALSE(motion.knows_velocity());
  motion.update(0.2, {}, planar(5.0, 0.0, 0.0), true, true);  // a pose graph correction moved the map
  EXPECT_FALSE(motion.knows_velocity());
  motion.update(0.3, {}, planar(6.0, 0.0, 0.0), true, false);
  EXPECT_TRUE(motion.knows_velocity());
  EXPECT_NEAR(motion.predict(0.4).x, 1.0, 1e-9);
}

TEST(ConstantVelocityPrediction, OnceTheVelocityIsKnownTheGuessMayBeOffByAChangeOfMotion) {
  ConstantVelocityPrediction motion(
      {.max_speed = 20.0, .max_turn_rate = 2.0, .max_acceleration = 5.0, .max_angular_acceleration = 4.0});
  motion.update(0.0, {}, planar(0.0, 0.0, 0.0), false, false);
  motion.update(0.1, {}, planar(0.1, 0.0, 0.0), true, false);
  ASSERT_TRUE(motion.knows_velocity());
  // 10 Hz: a little (a dt^2 / 2) beyond the fixed limits.
  EXPECT_NEAR(motion.uncertainty(0.2).translation, 0.025, 1e-9);
  EXPECT_NEAR(motion.uncertainty(0.2).rotation, 0.02, 1e-9);
  // A scan a second later (a slow stream, or scans dropped): a walker may have turned a corner.
  EXPECT_NEAR(motion.uncertainty(1.1).translation, 2.5, 1e-9);
  EXPECT_NEAR(motion.uncertainty(1.1).rotation, 2.0, 1e-9);
  // Never more than the fastest base could move at all since the last scan.
  EXPECT_NEAR(motion.uncertainty(10.1).translation, 200.0, 1e-9);
  EXPECT_NEAR(motion.uncertainty(10.1).rotation, 20.0, 1e-9);
}

}  // namespace
}  // namespace strata

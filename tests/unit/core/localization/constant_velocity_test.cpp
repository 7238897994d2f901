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
  const std::optional<GuessUncertainty> uncertainty = motion.uncertainty(5.1);
  ASSERT_TRUE(uncertainty.has_value());
  EXPECT_NEAR(uncertainty->translation, 2.0, 1e-9);
  EXPECT_NEAR(uncertainty->rotation, 0.2, 1e-9);
}

TEST(ConstantVelocityPrediction, TheMotionBetweenTwoScansIsCarriedOnPerSecond) {
  ConstantVelocityPrediction motion;
  // A car at 12 m/s turning 0.5 rad/s, scans 0.1 s apart; the map frame is turned against the odometry's.
  motion.update(10.0, {}, planar(3.0, 1.0, 0.5), false, false);
  const Eigen::Isometry3d second = planar(3.0, 1.0, 0.5) * planar(1.2, 0.0, 0.05);
  motion.update(10.1, {}, second, true, false);
  EXPECT_FALSE(motion.uncertainty(10.2).has_value());
  // 0.2 s later (a scan was dropped): twice the motion, in the base's frame.
  const Pose2 predicted = motion.predict(10.3);
  EXPECT_NEAR(predicted.x, 2.4, 1e-9);
  EXPECT_NEAR(predicted.y, 0.0, 1e-9);
  EXPECT_NEAR(predicted.theta, 0.1, 1e-9);
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
  EXPECT_TRUE(motion.uncertainty(0.2).has_value());
  motion.update(0.2, {}, planar(5.0, 0.0, 0.0), true, true);  // a pose graph correction moved the map
  EXPECT_TRUE(motion.uncertainty(0.3).has_value());
  motion.update(0.3, {}, planar(6.0, 0.0, 0.0), true, false);
  EXPECT_FALSE(motion.uncertainty(0.4).has_value());
  EXPECT_NEAR(motion.predict(0.4).x, 1.0, 1e-9);
}

}  // namespace
}  // namespace strata

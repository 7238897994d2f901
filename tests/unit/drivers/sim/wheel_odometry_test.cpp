#include "drivers/sim/wheel_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace strata::sim {
namespace {

constexpr double kSeparation = 0.6;

// Drives `steps` steps of a gentle arc and returns the final odometry pose.
Pose2 drive_arc(WheelOdometry& odometry, int steps) {
  for (int i = 0; i < steps; ++i)
    odometry.integrate({0.0099, 0.0101});
  return odometry.pose();
}

TEST(WheelOdometry, WithoutNoiseFollowsTheWheels) {
  WheelOdometry odometry(kSeparation, {.wheel_scale_stddev = 0.0, .slip_stddev = 0.0}, 1);
  for (int i = 0; i < 100; ++i)
    odometry.integrate({0.01, 0.01});
  EXPECT_NEAR(odometry.pose().x, 1.0, 1e-12);
  EXPECT_NEAR(odometry.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(odometry.distance(), 1.0, 1e-12);
}

TEST(WheelOdometry, TurnOnTheSpot) {
  WheelOdometry odometry(kSeparation, {.wheel_scale_stddev = 0.0, .slip_stddev = 0.0}, 1);
  odometry.integrate({-0.3, 0.3});  // each wheel rolls half the separation: one radian
  EXPECT_NEAR(odometry.pose().theta, 1.0, 1e-12);
  EXPECT_NEAR(odometry.pose().x, 0.0, 1e-12);
}

TEST(WheelOdometry, AGyroTurnReplacesTheWheels) {
  // The wheels say one radian (one slipped); the gyro says half of it: gyro-aided odometry turns by the
  // gyro and drives the wheels' mean distance.
  WheelOdometry odometry(kSeparation, {.wheel_scale_stddev = 0.0, .slip_stddev = 0.0}, 1);
  odometry.integrate({-0.3, 0.3}, 0.5);
  EXPECT_NEAR(odometry.pose().theta, 0.5, 1e-12);
  odometry.integrate({0.2, 0.2}, 0.0);
  EXPECT_NEAR(odometry.pose().theta, 0.5, 1e-12);
  EXPECT_NEAR(odometry.pose().x, 0.2 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(odometry.pose().y, 0.2 * std::sin(0.5), 1e-12);
}

TEST(WheelOdometry, SameSeedSameDrift) {
  WheelOdometry a(kSeparation, {}, 42);
  WheelOdometry b(kSeparation, {}, 42);
  WheelOdometry c(kSeparation, {}, 43);
  const Pose2 pa = drive_arc(a, 1000);
  const Pose2 pb = drive_arc(b, 1000);
  const Pose2 pc = drive_arc(c, 1000);
  EXPECT_EQ(pa.x, pb.x);
  EXPECT_EQ(pa.y, pb.y);
  EXPECT_EQ(pa.theta, pb.theta);
  EXPECT_NE(pa.x, pc.x);
}

TEST(WheelOdometry, DriftGrowsWithDistance) {
  // Over many seeds, the RMS position error after 40 m exceeds that after 10 m.
  WheelOdometry truth(kSeparation, {.wheel_scale_stddev = 0.0, .slip_stddev = 0.0}, 0);
  const Pose2 truth_short = drive_arc(truth, 1000);
  const Pose2 truth_long = drive_arc(truth, 3000);
  double short_sq = 0.0;
  double long_sq = 0.0;
  const int runs = 200;
  for (int seed = 1; seed <= runs; ++seed) {
    WheelOdometry noisy(kSeparation, {}, static_cast<std::uint64_t>(seed));
    const Pose2 s = drive_arc(noisy, 1000);
    const Pose2 l = drive_arc(noisy, 3000);
    short_sq += std::pow(s.x - truth_short.x, 2) + std::pow(s.y - truth_short.y, 2);
    long_sq += std::pow(l.x - truth_long.x, 2) + std::pow(l.y - truth_long.y, 2);
  }
  const double rms_short = std::sqrt(short_sq / runs);
  const double rms_long = std::sqrt(long_sq / runs);
  EXPECT_GT(rms_short, 0.0);
  EXPECT_GT(rms_long, 2.0 * rms_short);
  // A wheelchair drifts centimetres to decimetres over 10 m, not metres.
  EXPECT_LT(rms_short, 0.5);
}

}  // namespace
}  // namespace strata::sim

#include "drivers/sim/diff_drive_base.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/angles.hpp"

namespace strata::sim {
namespace {

void drive(DiffDriveBase& base, const VelocityCommand& command, double seconds, double dt = 0.01) {
  for (double t = 0.0; t < seconds - 1e-9; t += dt)
    base.apply(base.preview(command, dt));
}

TEST(DiffDriveBase, AcceleratesWithinTheLimit) {
  DiffDriveLimits limits;
  limits.max_accel = 0.5;
  DiffDriveBase base(limits);
  drive(base, {1.0, 0.0}, 1.0);
  EXPECT_NEAR(base.velocity().v, 0.5, 1e-9);  // 1 s at 0.5 m/s^2
  drive(base, {1.0, 0.0}, 2.0);
  EXPECT_NEAR(base.velocity().v, limits.max_speed, 1e-9);
}

TEST(DiffDriveBase, DrivesStraightAtConstantSpeed) {
  DiffDriveLimits limits;
  limits.max_accel = 1e9;  // instant acceleration isolates the kinematics
  DiffDriveBase base(limits);
  drive(base, {0.5, 0.0}, 2.0);
  EXPECT_NEAR(base.pose().x, 1.0, 1e-9);
  EXPECT_NEAR(base.pose().y, 0.0, 1e-12);
}

TEST(DiffDriveBase, ArcEndsOnTheCircle) {
  DiffDriveLimits limits;
  limits.max_accel = 1e9;
  limits.max_turn_accel = 1e9;
  DiffDriveBase base(limits);
  // A quarter circle of radius 1 m: v = 0.5 m/s, w = 0.5 rad/s, for pi seconds.
  drive(base, {0.5, 0.5}, kPi / 2 / 0.5, 0.001 * kPi);
  EXPECT_NEAR(base.pose().x, 1.0, 1e-6);
  EXPECT_NEAR(base.pose().y, 1.0, 1e-6);
  EXPECT_NEAR(base.pose().theta, kPi / 2, 1e-6);
}

TEST(DiffDriveBase, WheelTravelMatchesTheTurn) {
  DiffDriveLimits limits;
  limits.max_accel = 1e9;
  limits.max_turn_accel = 1e9;
  DiffDriveBase base(limits);
  const auto step = base.preview({0.0, 1.0}, 0.1);  // turn on the spot
  EXPECT_NEAR(step.wheels.left, -0.1 * limits.wheel_separation / 2, 1e-12);
  EXPECT_NEAR(step.wheels.right, 0.1 * limits.wheel_separation / 2, 1e-12);
}

TEST(DiffDriveBase, ClampsCommandsToTheLimits) {
  DiffDriveLimits limits;
  limits.max_accel = 1e9;
  limits.max_turn_accel = 1e9;
  DiffDriveBase base(limits);
  const auto step = base.preview({10.0, -10.0}, 0.01);
  EXPECT_DOUBLE_EQ(step.velocity.v, limits.max_speed);
  EXPECT_DOUBLE_EQ(step.velocity.w, -limits.max_turn_rate);
}

TEST(DiffDriveBase, HaltStops) {
  DiffDriveBase base(DiffDriveLimits{});
  drive(base, {1.0, 0.3}, 1.0);
  base.halt();
  EXPECT_EQ(base.velocity().v, 0.0);
  EXPECT_EQ(base.velocity().w, 0.0);
}

}  // namespace
}  // namespace strata::sim

#include "core/localization/pose_extrapolator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace strata {
namespace {

// The yard's ramps: up from x = -5 to -1 (0.4 m), a platform to x = 1, down to x = 5.
double ground_height(double x) {
  if (x < -5.0 || x > 5.0)
    return 0.0;
  if (x < -1.0)
    return 0.1 * (x + 5.0);
  if (x <= 1.0)
    return 0.4;
  return 0.4 - 0.1 * (x - 1.0);
}

/// The base's pitch there, driving east (+x): nose up (negative) on the way up.
double ground_pitch(double x) {
  if (x > -5.0 && x < -1.0)
    return -std::atan(0.1);
  if (x > 1.0 && x < 5.0)
    return std::atan(0.1);
  return 0.0;
}

GravityReading gravity_at(double x) {
  const double pitch = ground_pitch(x);
  return {.up_in_base = Eigen::Vector3d(-std::sin(pitch), 0.0, std::cos(pitch)), .sigma = 0.01};
}

/// Planar wheel odometry that started 10 m west of the map's origin and 0.02 rad off in heading.
Pose3 odometry_at(double x) {
  return Pose3::from_pose2(Pose2{x + 10.0, 0.0, 0.02});
}

Pose3 truth_at(double x) {
  Pose3 pose;
  pose.position = {x, 0.0, ground_height(x)};
  pose.pitch = ground_pitch(x);
  return pose;
}

/// The localizer's correction from a scan at `x`: it knows the truth there, tilt included.
Eigen::Isometry3d correction_at(double x) {
  return truth_at(x).to_isometry() * odometry_at(x).to_isometry().inverse();
}

/// Drives from `from` to `to` at 100 Hz and 0.5 m/s, stamps going on from `stamp`; returns the last stamp.
double drive(PoseExtrapolator& extrapolator, double from, double to, double stamp, bool with_gravity) {
  const double step = 0.005;
  for (double x = from; x <= to + 1e-9; x += step, stamp += 0.01)
    extrapolator.add_sample(stamp, odometry_at(x),
                            with_gravity ? std::optional<GravityReading>(gravity_at(x)) : std::nullopt);
  return stamp;
}

TEST(PoseExtrapolator, OverThePlatformAndDownTheFarRampTheHeightFollowsTheGround) {
  PoseExtrapolator extrapolator;
  // The last scan near the top of the up ramp; the next one will come on the down ramp.
  double stamp = drive(extrapolator, -3.0, -1.5, 100.0, true);
  extrapolator.set_correction(correction_at(-1.5), stamp - 0.01);
  drive(extrapolator, -1.5, 3.5, stamp, true);
  const Pose3 estimate = extrapolator.estimate();
  EXPECT_NEAR(estimate.position.x(), 3.5, 0.05);
  EXPECT_NEAR(estimate.position.z(), ground_height(3.5), 0.02)
      << "truth 0.25 m, the ramp's tilt carried says 0.85";
  EXPECT_NEAR(estimate.pitch, ground_pitch(3.5), 0.005) << "nose down, as the reading says";
  EXPECT_NEAR(estimate.yaw, 0.0, 1e-9);
}

TEST(PoseExtrapolator, TheReadingsAreTakenWithoutTheMountingErrorItIsGiven) {
  // An IMU mounted 0.5 degrees nose down about the base's y: on level ground it reads a climb.
  const Eigen::Vector3d mounting(0.0, 0.5 * std::numbers::pi / 180.0, 0.0);
  const Eigen::Matrix3d to_reading =
      Eigen::AngleAxisd(mounting.y(), Eigen::Vector3d::UnitY()).toRotationMatrix();
  const auto drive_level = [&](PoseExtrapolator& extrapolator) {
    double stamp = 100.0;
    for (double x = 6.0; x <= 16.0 + 1e-9; x += 0.005, stamp += 0.01) {
      GravityReading gravity{.up_in_base = to_reading * gravity_at(x).up_in_base, .sigma = 0.01};
      extrapolator.add_sample(stamp, odometry_at(x), gravity);
      if (x < 6.001)
        extrapolator.set_correction(correction_at(6.0), stamp);
    }
    return extrapolator.estimate();
  };
  PoseExtrapolator told;
  told.set_mounting_error(mounting);
  const Pose3 estimate = drive_level(told);
  EXPECT_NEAR(estimate.position.z(), 0.0, 1e-6);
  EXPECT_NEAR(estimate.pitch, 0.0, 1e-9);
  EXPECT_NEAR(estimate.roll, 0.0, 1e-9);

  PoseExtrapolator not_told;
  const Pose3 tilted = drive_level(not_told);
  EXPECT_GT(std::abs(tilted.position.z()), 0.08) << "10 m at 0.5 degrees: 0.087 m";
  EXPECT_NEAR(std::abs(tilted.pitch), mounting.y(), 1e-6);
}

TEST(PoseExtrapolator, WithoutGravityTheOdometryIsCarriedByTheCorrection) {
  PoseExtrapolator extrapolator;
  double stamp = drive(extrapolator, -3.0, -1.5, 100.0, false);
  extrapolator.set_correction(correction_at(-1.5), stamp - 0.01);
  drive(extrapolator, -1.5, 3.5, stamp, false);
  const Eigen::Isometry3d carried = correction_at(-1.5) * odometry_at(3.5).to_isometry();
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(carried, 1e-9));
}

TEST(PoseExtrapolator, ALidarAlonesPoseIsCarriedOnByItsVelocityBetweenScans) {
  // No odometry: the samples' odometry stands still, and the last scan's pose would be shown until the next.
  PoseExtrapolator extrapolator;
  Eigen::Isometry3d at_scan = Eigen::Isometry3d::Identity();
  at_scan.translation() = Eigen::Vector3d(2.0, 1.0, 0.5);
  at_scan.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  extrapolator.add_sample(10.0, Pose3{}, std::nullopt);
  extrapolator.set_correction(at_scan, 10.0);
  extrapolator.set_velocity(Pose2{1.0, 0.0, 0.2});  // 1 m/s forward, turning
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(at_scan, 1e-12)) << "at the scan: its pose";
  extrapolator.add_sample(10.5, Pose3{}, std::nullopt);
  const Eigen::Isometry3d expected =
      at_scan * Pose3::from_pose2(Pose2{0.5, 0.0, 0.1}).to_isometry();  // half a second on
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(expected, 1e-12));
  // Scans stopped coming: carried for at most a second, not on and on.
  extrapolator.add_sample(30.0, Pose3{}, std::nullopt);
  const Eigen::Isometry3d capped = at_scan * Pose3::from_pose2(Pose2{1.0, 0.0, 0.2}).to_isometry();
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(capped, 1e-12));
  // A base with odometry gives none: the odometry carries it.
  extrapolator.set_velocity(std::nullopt);
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(at_scan, 1e-12));
}

TEST(PoseExtrapolator, ACorrectionFromBeforeTheSamplesKeptIsCarriedAsItIs) {
  PoseExtrapolator extrapolator;
  drive(extrapolator, -3.0, 3.0, 100.0, true);
  // A replay started over (earlier stamps): the old samples are gone. A scan from before the new ones
  // has no height to start from.
  drive(extrapolator, 2.0, 3.0, 10.0, true);
  extrapolator.set_correction(correction_at(-1.5), 5.0);
  const Eigen::Isometry3d carried = correction_at(-1.5) * odometry_at(3.0).to_isometry();
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(carried, 1e-9));
}

TEST(PoseExtrapolator, AnUnusableReadingIsNone) {
  PoseExtrapolator extrapolator;
  double stamp = drive(extrapolator, -3.0, -1.5, 100.0, true);
  extrapolator.set_correction(correction_at(-1.5), stamp - 0.01);
  stamp = drive(extrapolator, -1.5, 0.0, stamp, true);
  extrapolator.add_sample(stamp, odometry_at(0.0),
                          GravityReading{.up_in_base = {0.0, 0.0, 2.0}, .sigma = 0.01});
  const Eigen::Isometry3d carried = correction_at(-1.5) * odometry_at(0.0).to_isometry();
  EXPECT_TRUE(extrapolator.estimate().to_isometry().isApprox(carried, 1e-9));
}

}  // namespace
}  // namespace strata

#include "core/localization/gravity_leveling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace strata {
namespace {

Eigen::Isometry3d pose_with(double roll, double pitch, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(3.0, -2.0, 1.0);
  return pose;
}

/// The angle between the map's up and the base's up as the pose has it: the tilt.
double tilt(const Eigen::Matrix3d& rotation) {
  return std::acos(std::clamp(rotation(2, 2), -1.0, 1.0));
}

/// The heading of the base's forward axis projected on the floor.
double heading(const Eigen::Matrix3d& rotation) {
  return std::atan2(rotation(1, 0), rotation(0, 0));
}

TEST(GravityLeveling, AlignPutsThePosesUpWhereGravitySays) {
  const Eigen::Isometry3d level = pose_with(0.0, 0.0, 0.7);
  Eigen::Isometry3d tilted = pose_with(0.05, -0.08, 0.7);
  // The base is level; the estimate says it is tilted.
  const GravityReading reading{.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.002};
  const GravityLeveling leveling;
  tilted.linear() = leveling.align(tilted, reading) * tilted.linear();
  EXPECT_NEAR(tilt(tilted.linear()), 0.0, 1e-4) << "an unknown start takes a sure reading nearly whole";
  EXPECT_NEAR(heading(tilted.linear()), heading(level.linear()), 0.01) << "gravity cannot see heading";
}

// Gravity tells tilt, not heading. A turn about a level axis moves a tilted pose's heading at second
// order: a guess pitched -3 and rolled -2 degrees, turned to a reading of -4 and 3 (a hill crossed
// slantwise), moved its heading 0.3 degrees. Both the guess's turn and the levelling keep it.
TEST(GravityLeveling, TiltCorrectionsKeepTheHeading) {
  const double degree = std::numbers::pi / 180.0;
  const double yaw = 22.4 * degree;
  const Eigen::Isometry3d estimate = pose_with(-2.0 * degree, -3.0 * degree, yaw);
  const Eigen::Isometry3d truth = pose_with(3.0 * degree, -4.0 * degree, yaw);
  const GravityReading reading{.up_in_base = truth.linear().transpose() * Eigen::Vector3d::UnitZ(),
                               .sigma = 0.002};
  const GravityLeveling unknown_start;
  const Eigen::Matrix3d aligned = unknown_start.align(estimate, reading) * estimate.linear();
  EXPECT_NEAR(heading(aligned), yaw, 1e-9);
  EXPECT_LT((aligned * reading.up_in_base - Eigen::Vector3d::UnitZ()).norm(), 1e-4)
      << "an unknown start takes a sure reading nearly whole";
  GravityLeveling leveling;
  const Eigen::Matrix3d levelled = leveling.level(estimate, reading) * estimate.linear();
  EXPECT_NEAR(heading(levelled), yaw, 1e-9);
  EXPECT_LT((levelled * reading.up_in_base - Eigen::Vector3d::UnitZ()).norm(), 1e-4);
}

// A guess a tenth of a metre on from the last scan (a 10 Hz lidar) mostly keeps the last scan's tilt
// against a reading as noisy as one taken while driving; one metres on (a tilting scanner's next stop)
// takes the reading, which knows a ramp begun; standing still, the last tilt stands.
TEST(GravityLeveling, AGuessTurnsTowardTheReadingByHowFarTheRobotMoved) {
  const Eigen::Isometry3d tilted = pose_with(0.05, 0.0, 0.7);
  const GravityReading noisy{.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.01};
  const GravityLeveling leveling;  // tilt_change_per_metre 0.1 rad
  const auto tilt_after = [&](std::optional<double> moved) {
    return tilt(leveling.align(tilted, noisy, moved) * tilted.linear());
  };
  // Nothing known of the motion, nor of the tilt (a start at the odometry's origin): nearly the whole turn.
  EXPECT_LT(tilt_after(std::nullopt), 0.05 * 0.02);
  EXPECT_NEAR(tilt_after(0.0), 0.05, 1e-9);
  EXPECT_NEAR(tilt_after(0.1), 0.025, 1e-3);  // change and noise alike (0.01 rad): half the way
  EXPECT_LT(tilt_after(0.02), 0.05 * 0.97);
  EXPECT_GT(tilt_after(0.02), 0.05 * 0.95);
  EXPECT_LT(tilt_after(2.0), 0.05 * 0.005);
}

// A start at a given pose (the simulator's spawn) knows its tilt: its first scan's guess keeps it against a
// reading taken while driving (0.01 rad of noise), which had tilted the whole run by half a degree.
TEST(GravityLeveling, AGivenStartKeepsItsTiltAgainstTheFirstNoisyReading) {
  const Eigen::Isometry3d level = pose_with(0.0, 0.0, 0.7);
  const GravityReading off{
      .up_in_base = Eigen::AngleAxisd(0.009, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ(),
      .sigma = 0.01};
  const GravityLeveling given({}, true);
  EXPECT_LT(tilt(given.align(level, off) * level.linear()), 0.009 * 0.1);
  const GravityLeveling unknown({}, false);
  EXPECT_GT(tilt(unknown.align(level, off) * level.linear()), 0.009 * 0.95);
}

TEST(GravityLeveling, TheFirstReadingIsTakenAndLaterOnesAreWeighedAgainstScanMatching) {
  GravityLeveling leveling;
  const GravityReading level{.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.002};
  // The first reading: the filter knows nothing of the tilt yet, so it takes gravity's almost whole.
  Eigen::Isometry3d pose = pose_with(0.1, 0.0, 0.0);
  pose.linear() = leveling.level(pose, level) * pose.linear();
  EXPECT_LT(tilt(pose.linear()), 0.001);
  // Settled, a reading that disagrees by 0.05 rad moves the pose part of the way, not all of it.
  for (int i = 0; i < 50; ++i)
    (void)leveling.level(pose_with(0.0, 0.0, 0.0), level);
  pose = pose_with(0.0, 0.05, 0.0);
  pose.linear() = leveling.level(pose, level) * pose.linear();
  EXPECT_GT(tilt(pose.linear()), 0.005);
  EXPECT_LT(tilt(pose.linear()), 0.045);
}

TEST(GravityLeveling, ANoisyReadingMovesThePoseLessThanASureOne) {
  GravityLeveling sure_filter;
  GravityLeveling noisy_filter;
  const Eigen::Isometry3d pose = pose_with(0.04, 0.0, 0.3);
  const Eigen::Matrix3d sure =
      sure_filter.level(pose, {.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.001}) * pose.linear();
  const Eigen::Matrix3d noisy =
      noisy_filter.level(pose, {.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.5}) * pose.linear();
  EXPECT_LT(tilt(sure), tilt(noisy));
}

TEST(GravityLeveling, AReadingThatIsNotAUnitVectorChangesNothing) {
  GravityLeveling leveling;
  const Eigen::Isometry3d pose = pose_with(0.1, 0.1, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double variance = leveling.variance();
  EXPECT_FALSE(GravityLeveling::usable({.up_in_base = {nan, 0.0, 1.0}, .sigma = 0.01}));
  EXPECT_FALSE(GravityLeveling::usable({.up_in_base = {0.0, 0.0, 1.0}, .sigma = -0.01}));
  EXPECT_TRUE(GravityLeveling::usable({.up_in_base = {0.0, 0.0, 1.0}, .sigma = 0.01}));
  EXPECT_TRUE(leveling.level(pose, {.up_in_base = {nan, 0.0, 1.0}, .sigma = 0.01}).isIdentity());
  EXPECT_TRUE(leveling.level(pose, {.up_in_base = {0.0, 0.0, 3.0}, .sigma = 0.01}).isIdentity());
  EXPECT_TRUE(leveling.level(pose, {.up_in_base = {0.0, 0.0, 1.0}, .sigma = 0.0}).isIdentity());
  EXPECT_TRUE(leveling.align(pose, {.up_in_base = {nan, 0.0, 1.0}, .sigma = 0.01}).isIdentity());
  EXPECT_EQ(leveling.variance(), variance);
  EXPECT_TRUE(leveling.bias().isZero());
}

TEST(GravityLeveling, TheImusMountingErrorIsLearntAsTheRobotTurns) {
  // The IMU is mounted 0.005 rad off about the base's x axis; scan matching keeps the pose level (the
  // truth). Turning, the reading's error stays put in the base frame, and is learnt as such.
  GravityLeveling leveling({}, /*start_given=*/true);
  const Eigen::Vector3d mounting(0.005, 0.0, 0.0);
  const GravityReading reading{
      .up_in_base = Eigen::AngleAxisd(0.005, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ(),
      .sigma = 0.003};
  const Eigen::Isometry3d first = pose_with(0.0, 0.0, 0.0);
  EXPECT_LT(tilt(leveling.level(first, reading) * first.linear()), 0.0025)
      << "a start whose tilt is known is not thrown over by the first reading";
  for (int i = 0; i < 400; ++i)
    (void)leveling.level(pose_with(0.0, 0.0, 0.05 * i), reading);
  EXPECT_NEAR((leveling.bias() - mounting).norm(), 0.0, 0.001);
  const GravityReading corrected = leveling.corrected(reading);
  EXPECT_NEAR((corrected.up_in_base - Eigen::Vector3d::UnitZ()).norm(), 0.0, 0.001);
}

}  // namespace
}  // namespace strata

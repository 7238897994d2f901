#include "core/localization/scan_to_map_localizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "core/geometry/angles.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "tests/support/corridor_world.hpp"
#include "tests/support/sim_saved_map.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

using test::corridor_scene;
using test::corridor_world;
using test::make_transform;
using test::room_scene;
using test::rotation_error;
using test::translation_error;

Pose2 planar(const Pose3& pose) {
  return {pose.position.x(), pose.position.y(), pose.yaw};
}

TEST(ScanToMapLocalizer, FirstScanKeepsTheGivenStart) {
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(1, 2, 0.5);
  ScanToMapLocalizer localizer({}, start);
  const PointCloud points = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const LocalizationUpdate update = localizer.add_scan(points, {0, 0, 0});
  EXPECT_FALSE(update.registration);
  EXPECT_EQ(update.correction, Correction::kNone);
  EXPECT_TRUE(update.pose.isApprox(start));
}

// A start at a given pose knows its tilt to the filter's sigma (0.002 rad), about as well as one reading
// (0.002 rad of noise and 0.002 of mounting error): its first scan takes the reading once, by the
// filter's gain (0.38), not twice (the guess's turn and then the levelling, 0.59 of it).
TEST(ScanToMapLocalizer, AGivenStartsFirstScanTakesItsReadingOnce) {
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(1, 2, 0.5);
  const double off = 0.005;
  const GravityReading reading{
      .up_in_base = Eigen::AngleAxisd(off, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ(),
      .sigma = std::hypot(0.002, 0.002)};
  ScanToMapLocalizer localizer({}, start);
  const PointCloud points = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const LocalizationUpdate update = localizer.add_scan(points, {0, 0, 0}, reading);
  const double tilt = std::acos(std::clamp(update.pose.linear()(2, 2), -1.0, 1.0));
  EXPECT_GT(tilt, 0.3 * off);
  EXPECT_LT(tilt, 0.45 * off);
}

TEST(ScanToMapLocalizer, AGravityReadingItCannotUseIsNotPassedOn) {
  const PointCloud points = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const GravityReading level{.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.01};
  EXPECT_TRUE(
      ScanToMapLocalizer({}, Eigen::Isometry3d::Identity()).add_scan(points, {0, 0, 0}, level).gravity);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const GravityReading& bad : {GravityReading{.up_in_base = {nan, 0.0, 1.0}, .sigma = 0.01},
                                    GravityReading{.up_in_base = {0.0, 0.0, 2.0}, .sigma = 0.01},
                                    GravityReading{.up_in_base = Eigen::Vector3d::UnitZ(), .sigma = 0.0}}) {
    ScanToMapLocalizer localizer({}, Eigen::Isometry3d::Identity());
    const LocalizationUpdate update = localizer.add_scan(points, {0, 0, 0}, bad);
    EXPECT_FALSE(update.gravity) << "the pose graph would take it as an attitude prior";
    EXPECT_TRUE(update.pose.linear().allFinite());
  }
}

// The robot moved 0.9 m but its wheels slipped: the odometry says it stood still. ICP finds the move, too
// far from the odometry's guess for the jump limit (0.5 m here); from the scans' own motion as a second
// guess, ICP finds it again, near that guess, and the scan is taken. A second guess that does not explain
// the move changes nothing.
TEST(ScanToMapLocalizer, AScanTooFarFromSlippingOdometryIsTakenFromTheSecondGuess) {
  LocalizerOptions options;
  options.registration.limits.max_translation_jump = 0.5;
  const PointCloud room = room_scene(0.1, 0.005, 7);
  const Eigen::Isometry3d truth = make_transform(0.9, 0.1, 0.0, 0.0, 0.0, 0.03);
  const PointCloud second_scan = transformed(room, truth.inverse());  // the room seen from there
  const auto localize = [&](const std::optional<Eigen::Isometry3d>& second_guess) {
    ScanToMapLocalizer localizer(options, Eigen::Isometry3d::Identity());
    static_cast<void>(localizer.add_scan(room, {0, 0, 0}));
    return localizer.add_scan(second_scan, {0, 0, 0}, std::nullopt, GuessSource::kOdometry, std::nullopt,
                              second_guess);
  };
  const LocalizationUpdate alone = localize(std::nullopt);
  ASSERT_TRUE(alone.registration);
  EXPECT_EQ(alone.registration->assessment.reason, RejectReason::kJumpFromGuess);
  EXPECT_EQ(alone.correction, Correction::kNone);

  const LocalizationUpdate retried = localize(make_transform(0.85, 0.05, 0.0, 0.0, 0.0, 0.02));
  EXPECT_TRUE(retried.retried);
  EXPECT_EQ(retried.correction, Correction::kFull);
  EXPECT_LT(translation_error(retried.pose, truth), 0.02);
  EXPECT_LT(rotation_error(retried.pose, truth), 0.005);

  const LocalizationUpdate elsewhere = localize(make_transform(0.3, -0.4, 0.0, 0.0, 0.0, -0.05));
  EXPECT_FALSE(elsewhere.retried);
  EXPECT_EQ(elsewhere.correction, Correction::kNone);
}

// A lidar alone in a corridor: once its motion is known, the corridor's axis comes from the prediction
// (partly corrected); before, the prediction (standing still) knows nothing, and ICP's answer is taken
// whole rather than pinning a moving robot where it stood.
TEST(ScanToMapLocalizer, BeforeTheMotionIsKnownNoDirectionIsTakenFromThePrediction) {
  // A corridor with a doorway's frame across it: the axis weakly constrained, above the fault check's
  // hard limit and below the localizer's guard (the weakest eigenvalue 0.015-0.016 whether 1,000 or 2,000
  // source points; a 1 m wide doorway gave 0.010-0.011, on the limit).
  PointCloud corridor = corridor_scene(0.1, 3);
  for (const double x : {-4.0, 2.0}) {
    for (double z = 0.0; z <= 2.5; z += 0.05) {
      for (double y = -1.0; y <= 1.0; y += 0.05) {
        if (std::abs(y) > 0.3 || z > 1.9)
          corridor.emplace_back(x, y, z);
      }
    }
  }
  const PointCloud second = transformed(corridor, make_transform(-0.2, 0.0, 0.0, 0.0, 0.0, 0.0));
  const auto localize = [&](bool motion_known) {
    ScanToMapLocalizer localizer({}, Eigen::Isometry3d::Identity());
    static_cast<void>(localizer.add_scan(corridor, {0, 0, 0}, std::nullopt, GuessSource::kPrediction));
    return localizer.add_scan(
        second, {0, 0, 0}, std::nullopt, GuessSource::kPrediction,
        GuessUncertainty{.translation = 0.1, .rotation = 0.01, .motion_known = motion_known});
  };
  const LocalizationUpdate known = localize(true);
  EXPECT_EQ(known.correction, Correction::kPartial);
  ASSERT_FALSE(known.odometry_directions.empty());
  EXPECT_GT(std::abs(known.odometry_directions[0].x()), 0.9);
  const LocalizationUpdate unknown = localize(false);
  EXPECT_EQ(unknown.correction, Correction::kFull) << unknown.registration->assessment.message;
  EXPECT_NEAR(unknown.pose.translation().x(), 0.2, 0.02) << "where ICP found it";
  EXPECT_TRUE(unknown.odometry_directions.empty());
}

// Drives the yard with stop-and-go scans and localizes them: the corrected pose must end closer to the
// truth than the odometry it started from, and climb the platform's ramp (odometry is planar).
TEST(ScanToMapLocalizer, BeatsOdometryInTheYard) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  sim::Simulator simulator(world, {.seed = 4});
  const Eigen::Isometry3d map_from_odom =
      simulator.sample().truth->to_isometry() * simulator.sample().odometry.to_isometry().inverse();
  ScanToMapLocalizer localizer({}, map_from_odom);
  std::size_t scans = 0;
  double highest = 0.0;
  while (scans < 14) {
    simulator.step(0.01);
    for (const ScanEvent& scan : simulator.take_scans()) {
      const LocalizationUpdate update =
          localizer.add_scan(pipeline::points_in_base(scan), planar(scan.odometry));
      highest = std::max(highest, update.pose.translation().z());
      ++scans;
    }
  }
  const RobotSample s = simulator.sample();
  const double corrected = (localizer.pose(planar(s.odometry)).translation() - s.truth->position).norm();
  const double odometry =
      ((map_from_odom * s.odometry.to_isometry()).translation() - s.truth->position).head<2>().norm();
  EXPECT_LT(corrected, odometry);
  EXPECT_LT(corrected, 0.3);
  EXPECT_GT(highest, 0.25);  // it saw itself go up the ramp onto the 0.4 m platform
}

// In a long featureless corridor ICP cannot tell how far the robot went: the localizer must take that
// from odometry (partial correction) instead of letting ICP slide.
TEST(ScanToMapLocalizer, CorridorAxisComesFromOdometry) {
  sim::Simulator simulator(corridor_world(/*ceiling=*/true), {.seed = 5});
  ScanToMapLocalizer localizer({}, Eigen::Isometry3d::Identity());
  std::size_t partial = 0, scans = 0;
  double worst_along = 0.0;
  while (scans < 6) {
    simulator.step(0.01);
    for (const ScanEvent& scan : simulator.take_scans()) {
      const LocalizationUpdate update =
          localizer.add_scan(pipeline::points_in_base(scan), planar(scan.odometry));
      if (update.correction == Correction::kPartial) {
        ++partial;
        // What it took from odometry, for the status (LocalizationHealth): the corridor's axis, x.
        ASSERT_EQ(update.odometry_directions.size(), 1u);
        EXPECT_GT(std::abs(update.odometry_directions[0].x()), 0.9);
      } else {
        EXPECT_TRUE(update.odometry_directions.empty());
        EXPECT_TRUE(update.odometry_axes.empty());
      }
      // Along the axis the estimate may be off by what odometry is off, not by a slide of metres.
      const double odometry_along = scan.odometry.position.x() - scan.truth->position.x();
      const double along = update.pose.translation().x() - scan.truth->position.x();
      worst_along = std::max(worst_along, std::abs(along - odometry_along));
      ++scans;
    }
  }
  EXPECT_GE(partial, 4u);
  EXPECT_LT(worst_along, 0.1);
}

// In the corridor every scan slides along its axis; taking none of ICP's turn, each keeps the odometry's
// heading: a heading drift handed in (HeadingDrift: the odometry's own, learnt elsewhere) turns each of
// those scans' guess, and the turns add up as the odometry's drift would have.
TEST(ScanToMapLocalizer, TheOdometrysHeadingDriftTurnsTheGuessOfAScanThatKeepsItsHeading) {
  sim::Simulator simulator(corridor_world(), {.seed = 5});
  LocalizerOptions options;
  options.sliding_yaw_weight = 0.0;
  ScanToMapLocalizer plain(options, Eigen::Isometry3d::Identity());
  ScanToMapLocalizer turned(options, Eigen::Isometry3d::Identity());
  constexpr double kDrift = 0.004;  // radians a scan
  std::size_t scans = 0;
  std::size_t kept = 0;  // scans since the first that kept the odometry's heading in both
  while (scans < 6) {
    simulator.step(0.01);
    for (const ScanEvent& scan : simulator.take_scans()) {
      const PointCloud points = pipeline::points_in_base(scan);
      const LocalizationUpdate a = plain.add_scan(points, planar(scan.odometry));
      const LocalizationUpdate b =
          turned.add_scan(points, planar(scan.odometry), std::nullopt, GuessSource::kOdometry, std::nullopt,
                          std::nullopt, scans == 0 ? 0.0 : kDrift);
      const auto keeps_heading = [](const LocalizationUpdate& u) {
        return std::ranges::any_of(u.odometry_axes,
                                   [](const Eigen::Vector3d& axis) { return axis.z() > 0.9; });
      };
      if (scans > 0) {
        ASSERT_TRUE(keeps_heading(a) && keeps_heading(b)) << "the corridor's scans slide";
        ++kept;
      }
      EXPECT_NEAR(heading_of(b.pose) - heading_of(a.pose), kDrift * static_cast<double>(kept), 2e-4);
      ++scans;
    }
  }
  EXPECT_GE(kept, 4u);
}

// The corridor's scans slide along its axis, but its walls resist turning: their heading is ICP's, so an
// odometry whose heading drifts (a gyro's bias) leaves the estimate's heading where the walls are. Taking
// none of ICP's turn, the estimate drifts with the odometry.
TEST(ScanToMapLocalizer, ThePartialScansOfACorridorTakeTheirHeadingFromItsWalls) {
  sim::Simulator simulator(corridor_world(), {.seed = 5});
  LocalizerOptions gyro_only;
  gyro_only.sliding_yaw_weight = 0.0;
  ScanToMapLocalizer weighed({}, Eigen::Isometry3d::Identity());
  ScanToMapLocalizer from_odometry(gyro_only, Eigen::Isometry3d::Identity());
  constexpr double kDrift = 0.004;  // radians a scan: the odometry's heading error grows by this
  std::optional<Pose2> last_truth;
  Pose2 drifted;
  std::size_t scans = 0;
  double worst_weighed = 0.0;
  double last_from_odometry = 0.0;
  while (scans < 8) {
    simulator.step(0.01);
    for (const ScanEvent& scan : simulator.take_scans()) {
      const Pose2 truth = planar(scan.odometry);
      // The odometry's own motion since the last scan, carried on from a heading that drifted.
      drifted = last_truth ? drifted.compose(truth.relative_to(*last_truth)) : truth;
      if (last_truth)
        drifted.theta += kDrift;
      last_truth = truth;
      const PointCloud points = pipeline::points_in_base(scan);
      const LocalizationUpdate a = weighed.add_scan(points, drifted);
      const LocalizationUpdate b = from_odometry.add_scan(points, drifted);
      if (scans > 0) {
        EXPECT_EQ(a.correction, Correction::kPartial) << "the corridor's scans slide along it";
        EXPECT_TRUE(std::ranges::none_of(a.odometry_axes, [](const Eigen::Vector3d& axis) {
          return axis.z() > 0.9;
        })) << "its heading is not the odometry's";
      }
      worst_weighed = std::max(worst_weighed, std::abs(wrap_angle(heading_of(a.pose) - scan.truth->yaw)));
      last_from_odometry = std::abs(wrap_angle(heading_of(b.pose) - scan.truth->yaw));
      ++scans;
    }
  }
  // Scans 2 m apart take 86 % of ICP's turn: what is left of a scan's drift does not add up.
  EXPECT_LT(worst_weighed, 1.5 * kDrift);
  EXPECT_GT(last_from_odometry, 5 * kDrift) << "the odometry's drift, kept";
}

// Between two scans a gyro drifts hundredths of a degree: a partial scan that ICP turns further from the
// guess than sliding_yaw_max_change found a false minimum (over open ground they turn 2-10 degrees), and the
// odometry's heading stands. Here the odometry's heading jumps 3 degrees at the third scan; the walls would
// undo it, as they do with the limit raised.
TEST(ScanToMapLocalizer, APartialScansTurnBeyondWhatAGyroDriftsIsNotTaken) {
  LocalizerOptions wide;
  wide.sliding_yaw_max_change = 0.2;  // radians: 11 degrees
  const auto heading_error_after_jump = [](const LocalizerOptions& options) {
    sim::Simulator simulator(corridor_world(), {.seed = 5});
    ScanToMapLocalizer localizer(options, Eigen::Isometry3d::Identity());
    constexpr double kJump = 3.0 * std::numbers::pi / 180.0;
    std::size_t scans = 0;
    double error = 0.0;
    while (scans < 4) {
      simulator.step(0.01);
      for (const ScanEvent& scan : simulator.take_scans()) {
        Pose2 odometry{scan.truth->position.x(), scan.truth->position.y(), scan.truth->yaw};
        if (scans >= 2)
          odometry.theta += kJump;
        const LocalizationUpdate update = localizer.add_scan(pipeline::points_in_base(scan), odometry);
        if (scans == 2)
          error = std::abs(wrap_angle(heading_of(update.pose) - scan.truth->yaw));
        ++scans;
      }
    }
    return error;
  };
  EXPECT_GT(heading_error_after_jump({}), 0.04) << "the odometry's 3 degrees (0.052 rad), kept";
  EXPECT_LT(heading_error_after_jump(wide), 0.01) << "ICP's turn, taken";
}

// A map saved from one run (its keyframes at their poses) and a second run that starts 0.5 m and 4 degrees
// from where it believes: localizing in the saved map, its first scan already lands where the robot is,
// and it stays there; mapping anew, the whole run keeps the error of its start (its map is its own).
TEST(ScanToMapLocalizer, LocalizesInASavedMapFromAWrongStart) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  auto saved = std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14));
  ASSERT_GT(saved->points.size(), 10000U);

  const auto run = [&](bool localize, double& first_error, double& last_error) {
    sim::Simulator simulator(world, {.seed = 2});
    Eigen::Isometry3d wrong = Eigen::Isometry3d::Identity();
    wrong.translation() = Eigen::Vector3d(0.4, -0.3, 0.0);
    wrong.linear() =
        Eigen::AngleAxisd(4.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The robot believes it stands 0.5 m and 4 degrees from where it does.
    const Eigen::Isometry3d believed =
        simulator.sample().truth->to_isometry() * wrong * simulator.sample().odometry.to_isometry().inverse();
    ScanToMapLocalizer localizer({}, believed);
    if (localize)
      localizer.localize_in(saved);
    std::size_t scans = 0;
    while (scans < 10) {
      simulator.step(0.01);
      for (const ScanEvent& scan : simulator.take_scans()) {
        const LocalizationUpdate update =
            localizer.add_scan(pipeline::points_in_base(scan), planar(scan.odometry));
        const double error = (update.pose.translation() - scan.truth->position).norm();
        if (scans++ == 0)
          first_error = error;
        last_error = error;
      }
    }
  };
  double first = 0.0, last = 0.0;
  run(true, first, last);
  EXPECT_LT(first, 0.1);
  EXPECT_LT(last, 0.1);
  run(false, first, last);
  EXPECT_GT(first, 0.4);
  EXPECT_GT(last, 0.3);
}

}  // namespace
}  // namespace strata

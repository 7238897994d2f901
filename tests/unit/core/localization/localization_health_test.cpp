#include "core/localization/localization_health.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

using enum LocalizationState;

/// Feeds scans as a stop-and-go robot driving along x takes them: `step` metres and `seconds` apart.
class Robot {
 public:
  explicit Robot(double step = 2.0, double seconds = 10.0) : step_(step), seconds_(seconds) {}

  LocalizationHealth first() { return add({}); }
  LocalizationHealth full(double rmse = 0.03) {
    ScanOutcome scan = registered(Correction::kFull);
    scan.rmse = rmse;
    return add(scan);
  }
  LocalizationHealth kept(RejectReason reason = RejectReason::kTooFewPairs) {
    ScanOutcome scan = registered(Correction::kNone);
    scan.reason = reason;
    scan.rmse = 0.2;
    return add(scan);
  }
  /// A corridor along x: the position along it comes from odometry.
  LocalizationHealth corridor() {
    ScanOutcome scan = registered(Correction::kPartial);
    scan.reason = RejectReason::kDegenerateGeometry;
    scan.odometry_directions = {Eigen::Vector3d::UnitX()};
    return add(scan);
  }
  /// A lidar alone in a corridor along x: the position along it is the prediction's, which may be
  /// `uncertainty` metres off.
  LocalizationHealth predicted_corridor(double uncertainty) {
    ScanOutcome scan = registered(Correction::kPartial);
    scan.predicted = true;
    scan.odometry_directions = {Eigen::Vector3d::UnitX()};
    scan.guess_uncertainty = uncertainty;
    return add(scan);
  }
  /// Open ground: nothing constrains the position in the plane nor the heading.
  LocalizationHealth open_ground() {
    ScanOutcome scan = registered(Correction::kPartial);
    scan.odometry_directions = {Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()};
    scan.odometry_axes = {Eigen::Vector3d(0.05, 0.0, -1.0).normalized()};
    return add(scan);
  }
  LocalizationHealth add(ScanOutcome scan) {
    scan.stamp = seconds_ * static_cast<double>(scans_);
    scan.position = {step_ * static_cast<double>(scans_), 0.0};
    ++scans_;
    classifier.classify(scan);
    return classifier.health();
  }

  LocalizationHealthClassifier classifier;

 private:
  static ScanOutcome registered(Correction correction) {
    ScanOutcome scan;
    scan.registered = true;
    scan.correction = correction;
    return scan;
  }
  double step_;
  double seconds_;
  std::size_t scans_ = 0;
};

TEST(LocalizationHealth, NamesTheThreeStates) {
  EXPECT_EQ(to_string(kOk), "ok");
  EXPECT_EQ(to_string(kDegraded), "degraded");
  EXPECT_EQ(to_string(kLost), "lost");
}

TEST(LocalizationHealth, BeforeTheFirstScanNothingConfirmedThePose) {
  const LocalizationHealth health = LocalizationHealthClassifier().health();
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "no scan yet: position from odometry only");
  EXPECT_EQ(health.state, LocalizationHealth::no_scan_yet().state);
}

TEST(LocalizationHealth, TheFirstScanStartsTheMapAndMatchedScansAreOk) {
  Robot robot;
  LocalizationHealth health = robot.first();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "first scan: the map starts here");
  health = robot.full();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "the last scan matched the map");
}

TEST(LocalizationHealth, ThreeScansInARowThatKeptOdometryAreDegraded) {
  Robot robot;
  robot.first();
  robot.full();
  LocalizationHealth health = robot.kept();
  EXPECT_EQ(health.state, kOk) << "one unmatched scan happens on any run";
  EXPECT_EQ(health.reason, "the last scan kept odometry: nothing to match");
  health = robot.kept();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "2 scans in a row kept odometry: nothing to match");
  health = robot.kept(RejectReason::kHighResidual);
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "3 scans in a row kept odometry: the surfaces did not fit");
  // One match ends it.
  health = robot.full();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "the last scan matched the map");
}

TEST(LocalizationHealth, TenScansWithoutAMatchAreLostAndAMatchRecovers) {
  Robot robot(0.5, 4.5);  // short steps: the count decides, not the distance
  robot.first();
  robot.full();  // at t = 4.5 s
  for (int i = 0; i < 9; ++i)
    EXPECT_EQ(robot.kept().state, i >= 2 ? kDegraded : kOk) << i;
  const LocalizationHealth lost = robot.kept();
  EXPECT_EQ(lost.state, kLost);
  EXPECT_EQ(lost.reason, "no scan matched for 10 scans (45 s, 5.0 m): position from odometry only");
  robot.kept();
  EXPECT_EQ(robot.classifier.health().state, kLost);
  EXPECT_EQ(robot.corridor().state, kOk) << "a partial match is a match";
}

TEST(LocalizationHealth, TwentyMetresOnOdometryAloneAreLost) {
  Robot robot(4.0, 10.0);  // far between scans: the distance decides before the count
  robot.first();
  robot.full();
  robot.kept();
  robot.kept();
  robot.kept();
  const LocalizationHealth sixteen = robot.kept();
  EXPECT_EQ(sixteen.state, kDegraded) << sixteen.reason;
  const LocalizationHealth twenty = robot.kept(RejectReason::kJumpFromGuess);
  EXPECT_EQ(twenty.state, kLost);
  EXPECT_EQ(twenty.reason, "no scan matched for 5 scans (50 s, 20 m): position from odometry only");
}

TEST(LocalizationHealth, ACorridorIsOkUntilOdometryCarriedItsAxisTenMetres) {
  Robot robot;  // 2 m between scans
  robot.first();
  robot.full();
  LocalizationHealth health = robot.corridor();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "corridor: position along x from odometry for 2.0 m");
  for (int i = 0; i < 3; ++i)
    health = robot.corridor();
  EXPECT_EQ(health.state, kOk) << health.reason;  // 8 m
  health = robot.corridor();
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "corridor: position along x from odometry for 10 m");
  // A scan that kept odometry on top of it: said too, as one unmatched scan.
  health = robot.kept();
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(
      health.reason,
      "corridor: position along x from odometry for 12 m; the last scan kept odometry: nothing to match");
  // A full match at the corridor's end.
  health = robot.full();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(robot.corridor().reason, "corridor: position along x from odometry for 2.0 m");
}

TEST(LocalizationHealth, OpenGroundNamesWhatOdometrySupplied) {
  Robot robot(3.0);
  robot.first();
  LocalizationHealth health = robot.open_ground();
  EXPECT_EQ(health.state, kOk);
  EXPECT_EQ(health.reason, "open ground: position along x,y and heading from odometry for 3.0 m");
  robot.open_ground();
  robot.open_ground();
  health = robot.open_ground();
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "open ground: position along x,y and heading from odometry for 12 m");
}

TEST(LocalizationHealth, ADiagonalCorridorIsAlongXAndY) {
  Robot robot;
  robot.first();
  ScanOutcome scan;
  scan.registered = true;
  scan.correction = Correction::kPartial;
  scan.odometry_directions = {Eigen::Vector3d(0.7, -0.7, 0.1).normalized()};
  // Only the part of the 2 m step along the corridor's axis was odometry's.
  EXPECT_EQ(robot.add(scan).reason, "corridor: position along x,y from odometry for 1.4 m");
}

TEST(LocalizationHealth, OnlyTheHeadingFromOdometry) {
  Robot robot;
  robot.first();
  ScanOutcome scan;
  scan.registered = true;
  scan.correction = Correction::kPartial;
  scan.odometry_axes = {Eigen::Vector3d::UnitZ()};
  // The walls fixed the position: the way driven is not odometry's.
  const LocalizationHealth health = robot.add(scan);
  EXPECT_EQ(health.reason, "few surfaces: heading from odometry");
  for (int i = 0; i < 10; ++i)
    robot.add(scan);
  EXPECT_EQ(robot.classifier.health().state, kOk) << "22 m with the heading alone from odometry";
}

TEST(LocalizationHealth, ALoopClosureEndsAStretchOnOdometry) {
  Robot robot;
  robot.first();
  for (int i = 0; i < 6; ++i)
    robot.corridor();
  ASSERT_EQ(robot.classifier.health().state, kDegraded);
  robot.classifier.confirm();  // a loop closure
  EXPECT_EQ(robot.classifier.health().state, kOk) << robot.classifier.health().reason;
  EXPECT_EQ(robot.corridor().reason, "corridor: position along x from odometry for 2.0 m")
      << "counted again from the loop";
}

TEST(LocalizationHealth, APlaceASearchFoundIsDegradedUntilTheNextScansConfirmIt) {
  Robot robot;
  robot.first();
  robot.full();
  robot.classifier.placed(20.0);
  LocalizationHealth health = robot.classifier.health();
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "placed by a search at t=20.0: waiting for the next scans to match there");
  EXPECT_EQ(robot.full().state, kDegraded) << "a matched scan alone does not confirm it";
  robot.classifier.confirm();  // the next scans matched there
  EXPECT_EQ(robot.classifier.health().state, kOk);
}

TEST(LocalizationHealth, AContradictedEstimateIsLostUntilConfirmed) {
  Robot robot;
  robot.first();
  robot.classifier.placed(10.0);
  robot.classifier.lose("the place a search found was wrong");
  EXPECT_EQ(robot.classifier.health().state, kLost);
  EXPECT_EQ(robot.classifier.health().reason, "the place a search found was wrong");
  EXPECT_EQ(robot.full().state, kLost) << "the scans register from the wrong place";
  robot.classifier.placed(30.0);
  EXPECT_EQ(robot.classifier.health().state, kDegraded) << "a new place, waiting for confirmation";
  robot.classifier.confirm();  // the next scans matched there
  EXPECT_EQ(robot.full().state, kOk);
}

// A lidar alone has no odometry: a refused scan keeps the motion's prediction, which nothing measured.
TEST(LocalizationHealth, ALidarAlonesRefusedScansAreDegradedAtOnceAndLostAtTheSecond) {
  Robot robot(1.0, 0.5);
  robot.first();
  robot.full();
  ScanOutcome refused;
  refused.registered = true;
  refused.predicted = true;
  refused.reason = RejectReason::kJumpFromGuess;
  LocalizationHealth health = robot.add(refused);
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason,
            "the last scan kept the prediction: the match was too far from the prediction to trust");
  health = robot.add(refused);
  EXPECT_EQ(health.state, kLost);
  EXPECT_EQ(health.reason, "no scan matched for 2 scans (1.0 s, 2.0 m): position from the prediction only");
  ScanOutcome matched = refused;
  matched.correction = Correction::kFull;
  EXPECT_EQ(robot.add(matched).state, kOk);
}

// After a gap in a lidar alone's scans, a road's scan matches along the road where the prediction put it.
TEST(LocalizationHealth, ADirectionFromAnUncertainPredictionIsDegraded) {
  Robot robot(1.0, 0.5);
  robot.first();
  EXPECT_EQ(robot.predicted_corridor(0.1).state, kOk);              // the next revolution of a 10 Hz lidar
  const LocalizationHealth health = robot.predicted_corridor(8.0);  // 4 s since the last scan
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason,
            "corridor: position along x from the prediction for 2.0 m, which may be 8.1 m off");
}

// Scan after scan along a corridor, a lidar alone's position along it is the prediction's: each prediction's
// possible error adds to the ones before, until the estimate may be a metre off; a scan matched whole ends
// it.
TEST(LocalizationHealth, PredictionsCarriedAlongACorridorAddUpTheirErrors) {
  Robot robot(0.01, 0.1);  // the prediction's stale 0.1 m/s: 0.4 m in 40 scans, short of 10 m
  robot.first();
  const double each = 0.025;  // a 10 Hz lidar's next revolution, 5 m/s^2 at most
  for (int i = 1; i < 40; ++i)
    ASSERT_EQ(robot.predicted_corridor(each).state, kOk) << "scan " << i;
  robot.predicted_corridor(each);
  const LocalizationHealth health = robot.predicted_corridor(each);
  EXPECT_EQ(health.state, kDegraded) << "41 scans: 1.025 m";
  EXPECT_NE(health.reason.find("which may be 1.0 m off"), std::string::npos) << health.reason;
  EXPECT_EQ(robot.full().state, kOk);
  EXPECT_EQ(robot.predicted_corridor(each).state, kOk) << "counted afresh after a whole match";
}

// How closely scans fit depends on what they see: a road's trees and cars fit looser than walls do.
TEST(LocalizationHealth, ALooseFitIsLooserThanTheRunsOwn) {
  Robot walls;
  walls.first();
  for (int i = 0; i < 10; ++i)
    walls.full(0.07);
  walls.full(0.11);
  walls.full(0.11);
  EXPECT_EQ(walls.full(0.11).state, kDegraded) << "1.5 times this run's 7 cm is 10.5 cm";
  Robot road;
  road.first();
  for (int i = 0; i < 10; ++i)
    road.full(0.10);
  road.full(0.125);
  road.full(0.125);
  EXPECT_EQ(road.full(0.125).state, kOk) << "this run fits at 10 cm: 15 cm is loose";
}

TEST(LocalizationHealth, ThreeLooseFitsInARowAreDegraded) {
  Robot robot;
  robot.first();
  for (int i = 0; i < 5; ++i)
    robot.full(0.05);
  EXPECT_EQ(robot.full(0.11).state, kOk) << "one loose fit happens on any run";
  EXPECT_EQ(robot.full(0.12).state, kOk);
  robot.kept();  // no fit at all: neither ends nor extends the streak
  const LocalizationHealth health = robot.full(0.112);
  EXPECT_EQ(health.state, kDegraded);
  EXPECT_EQ(health.reason, "3 scans in a row fit the map only loosely: the last 11 cm apart");
  EXPECT_EQ(robot.full(0.09).state, kOk);  // below the 10 cm limit
  robot.full(0.11);
  robot.full(0.11);
  EXPECT_EQ(robot.full(0.09).state, kOk) << "not three in a row";
}

}  // namespace
}  // namespace strata

#include "drivers/sim/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "drivers/sim/world/world_file.hpp"

namespace strata::sim {
namespace {

std::shared_ptr<const World> builtin(const char* name) {
  return std::make_shared<const World>(builtin_world(name));
}

TEST(Simulator, SameSeedSameRunAndScans) {
  auto world = builtin("yard");
  Simulator a(world, {.seed = 7});
  Simulator b(world, {.seed = 7});
  std::vector<ScanEvent> scans_a, scans_b;
  for (int i = 0; i < 2000; ++i) {
    a.step(0.01);
    b.step(0.01);
    for (auto& s : a.take_scans())
      scans_a.push_back(std::move(s));
    for (auto& s : b.take_scans())
      scans_b.push_back(std::move(s));
  }
  EXPECT_EQ(a.sample().odometry.position, b.sample().odometry.position);
  EXPECT_EQ(a.sample().truth->position, b.sample().truth->position);
  EXPECT_NEAR(a.sample().stamp, 20.0, 1e-9);
  ASSERT_FALSE(scans_a.empty());
  ASSERT_EQ(scans_a.size(), scans_b.size());
  for (std::size_t i = 0; i < scans_a.size(); ++i)
    EXPECT_EQ(scans_a[i].points, scans_b[i].points);
}

TEST(Simulator, YardRouteWithoutGettingStuck) {
  Simulator sim(builtin("yard"), {.scanner = ScannerKind::kNone});
  const Eigen::Vector3d start = sim.sample().truth->position;
  double farthest = 0.0;
  double highest = 0.0;
  for (int i = 0; i < 24000; ++i) {  // four simulated minutes: more than two laps
    sim.step(0.01);
    const RobotSample s = sim.sample();
    ASSERT_TRUE(s.blocked_by.empty())
        << s.blocked_by << " at t=" << s.stamp << " (" << s.truth->position.transpose() << ")";
    farthest = std::max(farthest, (s.truth->position - start).norm());
    highest = std::max(highest, s.truth->position.z());
  }
  EXPECT_GT(farthest, 10.0);
  EXPECT_NEAR(highest, 0.4, 1e-6);  // it drove over the platform
}

TEST(Simulator, CampusLapGoesOverAndUnderTheBridge) {
  Simulator sim(builtin("campus"), {.scanner = ScannerKind::kNone});
  bool on_deck = false;
  bool under_deck = false;
  bool in_hallway = false;
  double steepest = 0.0;
  for (int i = 0; i < 90000; ++i) {  // 15 simulated minutes: one lap is about 13
    sim.step(0.01);
    const RobotSample s = sim.sample();
    ASSERT_TRUE(s.blocked_by.empty())
        << s.blocked_by << " at t=" << s.stamp << " (" << s.truth->position.transpose() << ")";
    const Eigen::Vector3d& p = s.truth->position;
    const bool below_bridge = p.x() > 76 && p.x() < 92 && p.y() > -30 && p.y() < -27.5;
    on_deck = on_deck || (below_bridge && p.z() > 2.9);
    under_deck = under_deck || (below_bridge && p.z() < 0.1);
    in_hallway =
        in_hallway || (p.x() > 20 && p.x() < 40 && p.y() > 4 && p.y() < 6.5 && std::abs(p.z() - 0.45) < 1e-6);
    steepest = std::max(steepest, std::abs(s.truth->pitch));
  }
  EXPECT_TRUE(on_deck);
  EXPECT_TRUE(under_deck);
  EXPECT_TRUE(in_hallway);
  EXPECT_GT(steepest, 0.09);  // it tilted on the ramps (1:10 is 5.7 degrees)
}

TEST(Simulator, OdometryDriftsFromTheTruth) {
  Simulator sim(builtin("yard"), {.seed = 3, .scanner = ScannerKind::kNone});
  double travelled = 0.0;
  Eigen::Vector3d last = sim.sample().truth->position;
  for (int i = 0; i < 6000; ++i) {
    sim.step(0.01);
    travelled += (sim.sample().truth->position - last).norm();
    last = sim.sample().truth->position;
  }
  const RobotSample s = sim.sample();
  const double error = (s.odometry.position.head<2>() - s.truth->position.head<2>()).norm();
  EXPECT_GT(travelled, 20.0);
  EXPECT_GT(error, 1e-3);
  EXPECT_LT(error, 0.15 * travelled);       // an uncalibrated wheelchair: percents of the distance
  EXPECT_EQ(s.odometry.position.z(), 0.0);  // wheel odometry is planar
}

TEST(Simulator, StopAndGoStandsStillWhileScanning) {
  Simulator sim(builtin("yard"), {.seed = 2, .scanner = ScannerKind::kTilting});
  std::vector<ScanEvent> scans;
  Eigen::Vector3d scan_start_position;
  bool was_scanning = false;
  for (int i = 0; i < 6000 && scans.size() < 3; ++i) {
    sim.step(0.01);
    const RobotSample s = sim.sample();
    if (s.scanning && !was_scanning)
      scan_start_position = s.truth->position;
    if (s.scanning) {
      EXPECT_EQ(s.velocity.v, 0.0);
      EXPECT_EQ(s.truth->position, scan_start_position);
    }
    was_scanning = s.scanning;
    for (auto& scan : sim.take_scans())
      scans.push_back(std::move(scan));
  }
  ASSERT_EQ(scans.size(), 3u);
  for (const auto& scan : scans) {
    EXPECT_EQ(scan.sensor, "tilting-laser");
    EXPECT_GT(scan.points.size(), scan.rays / 2);
    ASSERT_TRUE(scan.truth);
    // What the gyro read while the base stood for the scan: at least the scan's time, its bias.
    ASSERT_TRUE(scan.standing_gyro);
    EXPECT_GE(scan.standing_gyro->seconds, scan.duration - 0.02);
    EXPECT_NEAR(scan.standing_gyro->sigma, 1.7e-4 / std::sqrt(scan.standing_gyro->seconds), 1e-12);
    EXPECT_NEAR(scan.standing_gyro->rate, sim.imu()->gyro_bias(), 5.0 * scan.standing_gyro->sigma);
  }
  // The robot moved about the scan spacing between scans.
  const double moved = (scans[2].truth->position - scans[1].truth->position).norm();
  EXPECT_NEAR(moved, 2.0, 0.3);
}

TEST(Simulator, ACommandReplacesTheDemoRouteForGood) {
  Simulator sim(builtin("yard"), {.scanner = ScannerKind::kNone});
  EXPECT_TRUE(sim.following_route());
  sim.command({0.0, 0.5});  // turn on the spot
  EXPECT_FALSE(sim.following_route());
  const Eigen::Vector3d start = sim.sample().truth->position;
  for (int i = 0; i < 200; ++i)
    sim.step(0.01);
  EXPECT_LT((sim.sample().truth->position - start).norm(), 0.01);
  EXPECT_NEAR(sim.sample().velocity.w, 0.5, 1e-9);
  sim.command({});
  for (int i = 0; i < 200; ++i)
    sim.step(0.01);
  EXPECT_EQ(sim.sample().velocity.v, 0.0);  // stays stopped: the route does not come back
  EXPECT_EQ(sim.sample().velocity.w, 0.0);
}

TEST(Simulator, StopAndGoHoldsACommandedRobotWhileScanning) {
  Simulator sim(builtin("yard"), {.seed = 2,
                                  .scanner = ScannerKind::kTilting,
                                  .tilting = {.slice_step_deg = 3.0, .rotation_step_deg = 6.0}});  // coarse
  sim.command({0.5, 0.0});
  int scans = 0;
  for (int i = 0; i < 3000 && scans < 2; ++i) {
    sim.step(0.01);
    if (sim.sample().scanning) {
      EXPECT_EQ(sim.sample().velocity.v, 0.0);
    }
    scans += static_cast<int>(sim.take_scans().size());
  }
  EXPECT_EQ(scans, 2);  // the first at the start, the second 2 m on
}

TEST(Simulator, AnOperatorDrivingByHandIsNotStoppedToScanTheBaseScansWhenTheyLetGo) {
  // Issue 63: under a held joystick the robot stood for a scan every 2 m.
  Simulator sim(builtin("yard"), {.seed = 2,
                                  .scanner = ScannerKind::kTilting,
                                  .tilting = {.slice_step_deg = 3.0, .rotation_step_deg = 6.0}});  // coarse
  sim.command({.v = 0.5, .w = 0.0, .by_hand = true});  // from the start, when the schedule owes a scan
  int scans = 0;
  double travelled = 0.0;
  for (int i = 0; i < 1200; ++i) {  // 12 s: 6 m at 0.5 m/s, three scans' spacing
    sim.step(0.01);
    EXPECT_FALSE(sim.sample().scanning) << "at " << sim.sample().stamp << " s";
    travelled += sim.sample().velocity.v * 0.01;
    scans += static_cast<int>(sim.take_scans().size());
  }
  EXPECT_EQ(scans, 0);
  EXPECT_GT(travelled, 5.5);
  sim.command({});  // let go: the base stops and takes the scan it owes
  for (int i = 0; i < 3000 && scans == 0; ++i) {
    sim.step(0.01);
    scans += static_cast<int>(sim.take_scans().size());
  }
  EXPECT_EQ(scans, 1);
  // A scan under way when the operator takes the joystick again is dropped: the robot moves at once.
  sim.command({.v = 0.5, .w = 0.0, .by_hand = false});
  while (!sim.sample().scanning && sim.sample().stamp < 60.0)  // 2 m on
    sim.step(0.01);
  ASSERT_TRUE(sim.sample().scanning) << "a goal's drive still stops to scan every 2 m";
  sim.command({.v = 0.5, .w = 0.0, .by_hand = true});
  sim.step(0.01);
  sim.step(0.01);
  EXPECT_FALSE(sim.sample().scanning);
  EXPECT_GT(sim.sample().velocity.v, 0.0);
}

TEST(Simulator, LidarScansWhileDriving) {
  Simulator sim(builtin("yard"), {.scanner = ScannerKind::kLidar});
  std::vector<ScanEvent> scans;
  for (int i = 0; i < 300; ++i) {
    sim.step(0.01);
    for (auto& scan : sim.take_scans())
      scans.push_back(std::move(scan));
  }
  EXPECT_EQ(scans.size(), 30u);  // 10 Hz for 3 s, the first revolution starting at once
  EXPECT_GT(sim.sample().velocity.v, 0.1);
  EXPECT_EQ(scans.back().sensor, "vlp16");
  EXPECT_FALSE(scans.back().standing_gyro) << "a driving base has no stand to read its gyro's bias in";
}

}  // namespace
}  // namespace strata::sim

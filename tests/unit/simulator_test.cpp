#include "drivers/sim/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace strata::sim {
namespace {

TEST(Simulator, SameSeedSameRun) {
  Simulator a = Simulator::yard({.seed = 7});
  Simulator b = Simulator::yard({.seed = 7});
  for (int i = 0; i < 2000; ++i) {
    a.step(0.01);
    b.step(0.01);
  }
  const RobotSample sa = a.sample();
  const RobotSample sb = b.sample();
  EXPECT_EQ(sa.odometry.position, sb.odometry.position);
  EXPECT_EQ(sa.truth.position, sb.truth.position);
  EXPECT_NEAR(sa.stamp, 20.0, 1e-9);
}

TEST(Simulator, DrivesTheLoopWithoutBumping) {
  Simulator sim = Simulator::yard();
  const auto start = sim.sample().truth.position;
  double farthest = 0.0;
  // Three simulated minutes: more than two laps of the loop.
  for (int i = 0; i < 18000; ++i) {
    sim.step(0.01);
    const RobotSample s = sim.sample();
    ASSERT_FALSE(s.bumped) << "bumped at t=" << s.stamp << " (" << s.truth.position.x() << ", "
                           << s.truth.position.y() << ")";
    farthest = std::max(farthest, (s.truth.position - start).norm());
  }
  EXPECT_GT(farthest, 5.0);  // it went around, not in place
}

TEST(Simulator, OdometryDriftsFromTheTruth) {
  Simulator sim = Simulator::yard({.seed = 3});
  for (int i = 0; i < 6000; ++i)
    sim.step(0.01);
  const RobotSample s = sim.sample();
  const double error = (s.odometry.position - s.truth.position).norm();
  EXPECT_GT(error, 1e-4);
  EXPECT_LT(error, 2.0);
}

TEST(Simulator, StopsAtAnObstacleInsteadOfPassingThrough) {
  // A wall straight across the loop's first leg.
  World world(10.0, {{"wall", {3.0, -6.0, 0.0}, {3.2, 0.0, 1.0}}});
  Simulator sim(std::move(world), LoopDriver({{8.0, -3.5}, {8.0, 3.0}}, 0.6, 1.0),
                {.start = {0.0, -3.5, 0.0}});
  bool bumped = false;
  for (int i = 0; i < 3000; ++i) {
    sim.step(0.01);
    bumped = bumped || sim.sample().bumped;
    ASSERT_LT(sim.sample().truth.position.x(), 3.0 - 0.45 + 1e-9);
  }
  EXPECT_TRUE(bumped);
}

}  // namespace
}  // namespace strata::sim

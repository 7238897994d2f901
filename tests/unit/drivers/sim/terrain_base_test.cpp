#include "drivers/sim/terrain_base.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace strata::sim {
namespace {

// Flat ground with a 1:10 ramp up to a platform, a curb, stairs, a steep ramp and a wall.
World test_world() {
  WorldDescription d;
  d.ramps.push_back({"ramp", {5, 0}, 10, 3, 0.0, 0.0, 0.0, 1.0});     // x in [0, 10], top 0 -> 1
  d.boxes.push_back({"platform", {12, 0, 0.5}, {4, 3, 1}, 0.0});      // x in [10, 14], top 1
  d.boxes.push_back({"curb", {5, 10, 0.06}, {10, 2, 0.12}, 0.0});     // y in [9, 11], 0.12 high
  d.boxes.push_back({"wall", {-5, -10, 1.5}, {0.2, 10, 3}, 0.0});     // x = -5
  d.ramps.push_back({"steep", {5, -10}, 4, 3, 0.0, 0.0, 0.0, 0.85});  // about 12 degrees
  std::vector<double> flat(61 * 61, 0.0);
  d.terrain = HeightField({-30, -30}, 1.0, 61, 61, flat);
  return World(std::move(d));
}

// Drives straight from `start` along its heading in 1 cm steps; returns the last stance and the reason
// it stopped (empty if it covered `distance`).
std::pair<Stance, std::string> drive(const TerrainPlacer& placer, Pose2 start, double distance) {
  Stance stance = placer.spawn(start, 0.0);
  Pose2 pose = start;
  const int steps = static_cast<int>(std::lround(distance / 0.01));
  for (int step = 0; step < steps; ++step) {
    pose = pose.compose({0.01, 0, 0});
    const auto result = placer.move(stance, pose);
    if (!result.ok)
      return {stance, result.blocked_by};
    stance = result.stance;
  }
  return {stance, ""};
}

TEST(TerrainPlacer, StandsLevelOnFlatGround) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const Stance stance = placer.spawn({-10, 0, 0.3}, 0.0);
  EXPECT_NEAR(stance.pose.position.z(), 0.0, 1e-9);
  EXPECT_NEAR(stance.pose.roll, 0.0, 1e-9);
  EXPECT_NEAR(stance.pose.pitch, 0.0, 1e-9);
  EXPECT_NEAR(stance.pose.yaw, 0.3, 1e-12);
}

TEST(TerrainPlacer, ClimbsTheRampTiltedAtItsSlope) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const auto [stance, blocked] = drive(placer, {-2, 0, 0}, 7);  // to x = 5, mid-ramp
  EXPECT_EQ(blocked, "");
  EXPECT_NEAR(stance.pose.position.z(), 0.5, 1e-6);       // top z = x / 10
  EXPECT_NEAR(stance.pose.pitch, -std::atan(0.1), 1e-6);  // nose up is negative pitch
  EXPECT_NEAR(stance.pose.roll, 0.0, 1e-9);
  // Across the slope (heading +y on the ramp) the robot rolls instead.
  Stance across = placer.spawn({5, -0.5, 3.14159265358979 / 2}, 0.6);
  EXPECT_NEAR(across.pose.roll, -std::atan(0.1), 1e-6);  // left side (west, -x) is lower
  EXPECT_NEAR(across.pose.pitch, 0.0, 1e-6);
}

TEST(TerrainPlacer, DrivesOntoThePlatform) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const auto [stance, blocked] = drive(placer, {-2, 0, 0}, 14);
  EXPECT_EQ(blocked, "");
  EXPECT_NEAR(stance.pose.position.z(), 1.0, 1e-6);
  EXPECT_NEAR(stance.pose.pitch, 0.0, 1e-6);
}

TEST(TerrainPlacer, CurbIsTooHigh) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const auto [stance, blocked] = drive(placer, {5, 6, 3.14159265358979 / 2}, 5);  // north into the curb
  // The footrests touch it first or the wheels refuse the step: either way it stays below.
  EXPECT_TRUE(blocked == "step" || blocked == "obstacle") << blocked;
  EXPECT_LT(stance.pose.position.y(), 9.0 - 0.3);
  EXPECT_NEAR(stance.pose.position.z(), 0.0, 1e-9);
}

TEST(TerrainPlacer, SteepRampIsRefused) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const auto [stance, blocked] = drive(placer, {0, -10, 0}, 6);
  EXPECT_EQ(blocked, "slope");
  EXPECT_LT(stance.pose.position.x(), 4.0);
}

TEST(TerrainPlacer, WallIsAnObstacle) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  const auto [stance, blocked] = drive(placer, {0, -10, 3.14159265358979}, 6);  // west into the wall
  EXPECT_EQ(blocked, "obstacle");
  EXPECT_GT(stance.pose.position.x(), -5.0 + 0.5);
}

TEST(TerrainPlacer, FallingOffAnEdgeIsAStep) {
  const World world = test_world();
  const TerrainPlacer placer(world, {});
  // Off the platform's end (1 m drop).
  Stance on_top = placer.spawn({12, 0, 0}, 1.0);
  EXPECT_NEAR(on_top.pose.position.z(), 1.0, 1e-9);
  Pose2 pose{12, 0, 0};
  std::string blocked;
  for (int i = 0; i < 300 && blocked.empty(); ++i) {
    pose = pose.compose({0.01, 0, 0});
    const auto result = placer.move(on_top, pose);
    if (result.ok)
      on_top = result.stance;
    else
      blocked = result.blocked_by;
  }
  EXPECT_EQ(blocked, "step");
}

}  // namespace
}  // namespace strata::sim

#include "drivers/sim/world/world.hpp"

#include <gtest/gtest.h>

namespace strata::sim {
namespace {

// A road under a bridge deck, a wall, a pole, flat terrain at z = 0.
World bridge_world() {
  WorldDescription d;
  d.boxes.push_back({"deck", {0, 0, 2.85}, {4, 20, 0.3}, 0.0});  // z in [2.7, 3.0]
  d.boxes.push_back({"wall", {30, 0, 1.5}, {0.2, 40, 3}, 0.0});
  d.cylinders.push_back({{-10, 0}, 0.2, 0.0, 4.0});
  std::vector<double> flat(41 * 41, 0.0);
  d.terrain = HeightField({-20, -20}, 1.0, 41, 41, flat);
  return World(std::move(d));
}

TEST(World, NearestSurfaceWins) {
  const World world = bridge_world();
  // Looking east from the pole's side at 1 m height: the wall at x = 29.9 (the deck is overhead).
  const auto hit = world.cast({{-5, 0, 1}, {1, 0, 0}}, 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 34.9, 1e-9);
  // Looking west: the pole.
  EXPECT_NEAR(world.cast({{-5, 0, 1}, {-1, 0, 0}}, 100)->distance, 4.8, 1e-9);
  // Straight down: the ground; up from under the deck: the deck's underside.
  EXPECT_NEAR(world.cast({{0, 0, 1}, {0, 0, -1}}, 100)->distance, 1.0, 1e-9);
  EXPECT_NEAR(world.cast({{0, 0, 1}, {0, 0, 1}}, 100)->distance, 1.7, 1e-9);
  // Out of range, and into the open sky.
  EXPECT_FALSE(world.cast({{-5, 0, 1}, {1, 0, 0}}, 30));
  EXPECT_FALSE(world.cast({{5, 5, 1}, Eigen::Vector3d(1, 1, 1).normalized()}, 100));
}

TEST(World, LongRaysCrossTheGrid) {
  const World world = bridge_world();
  // A shallow diagonal ray that crosses many grid cells before it reaches the wall.
  const Eigen::Vector3d direction = Eigen::Vector3d(1, 0.3, 0).normalized();
  const auto hit = world.cast({{-19, -12, 0.5}, direction}, 200);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point.x(), 29.9, 1e-9);
}

TEST(World, SurfaceBelowKnowsTheLevels) {
  const World world = bridge_world();
  EXPECT_NEAR(*world.surface_below(0, 0, 3.5), 3.0, 1e-9);  // on the deck
  EXPECT_NEAR(*world.surface_below(0, 0, 1.0), 0.0, 1e-9);  // on the road under it
  EXPECT_NEAR(*world.surface_below(10, 0, 1.0), 0.0, 1e-9);
  EXPECT_FALSE(world.surface_below(100, 0, 1.0));  // off the world
}

TEST(World, InsideSolid) {
  const World world = bridge_world();
  EXPECT_TRUE(world.inside_solid({0, 0, 2.8}));
  EXPECT_FALSE(world.inside_solid({0, 0, 2.0}));
  EXPECT_TRUE(world.inside_solid({30, 5, 1}));
  EXPECT_TRUE(world.inside_solid({5, 5, -0.5}));  // under the terrain
  EXPECT_FALSE(world.inside_solid({5, 5, 0.5}));
}

}  // namespace
}  // namespace strata::sim

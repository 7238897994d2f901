#include "drivers/sim/world.hpp"

#include <gtest/gtest.h>

namespace strata::sim {
namespace {

TEST(World, CollidesWithABoxWithinTheRadius) {
  const World world(10.0, {{"box", {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}}});
  EXPECT_TRUE(world.collides(0.5, 0.5, 0.1, 1.0));   // inside
  EXPECT_TRUE(world.collides(1.3, 0.5, 0.4, 1.0));   // 0.3 m from the face, radius 0.4
  EXPECT_FALSE(world.collides(1.5, 0.5, 0.4, 1.0));  // 0.5 m from the face
  EXPECT_FALSE(world.collides(1.3, 1.3, 0.4, 1.0));  // corner distance 0.42 m
}

TEST(World, PassesUnderAHighBox) {
  const World world(10.0, {{"shelf", {0.0, 0.0, 2.0}, {1.0, 1.0, 2.2}}});
  EXPECT_FALSE(world.collides(0.5, 0.5, 0.3, 1.3));
  EXPECT_TRUE(world.collides(0.5, 0.5, 0.3, 2.5));
}

TEST(World, YardHasAFenceAndObstacles) {
  const World yard = World::yard();
  EXPECT_GE(yard.boxes().size(), 5u);
  EXPECT_TRUE(yard.collides(yard.half_extent() - 0.1, 0.0, 0.3, 1.0));
  EXPECT_FALSE(yard.collides(3.0, -3.0, 0.45, 1.3));
}

}  // namespace
}  // namespace strata::sim

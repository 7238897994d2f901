#include "drivers/sim/world/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/geometry/angles.hpp"

namespace strata::sim {
namespace {

Ray ray(Eigen::Vector3d origin, Eigen::Vector3d direction) {
  return {origin, direction.normalized()};
}

TEST(ConvexSolid, BoxDistancesAreExact) {
  const auto box = ConvexSolid::box({0, 0, 1}, {2, 2, 2}, 0.0);  // x, y in [-1, 1], z in [0, 2]
  EXPECT_DOUBLE_EQ(*box.intersect(ray({-5, 0, 1}, {1, 0, 0}), 0, 100), 4.0);
  EXPECT_DOUBLE_EQ(*box.intersect(ray({0, 0, 10}, {0, 0, -1}), 0, 100), 8.0);
  EXPECT_FALSE(box.intersect(ray({-5, 3, 1}, {1, 0, 0}), 0, 100));           // passes beside
  EXPECT_FALSE(box.intersect(ray({-5, 0, 1}, {-1, 0, 0}), 0, 100));          // points away
  EXPECT_FALSE(box.intersect(ray({-5, 0, 1}, {1, 0, 0}), 0, 3.9));           // out of range
  EXPECT_DOUBLE_EQ(*box.intersect(ray({0, 0, 1}, {1, 0, 0}), 0, 100), 0.0);  // starts inside
}

TEST(ConvexSolid, YawedBox) {
  // A 2 x 2 box turned 45 degrees: its corner points along +x at sqrt(2) from the centre.
  const auto box = ConvexSolid::box({0, 0, 1}, {2, 2, 2}, kPi / 4);
  EXPECT_NEAR(*box.intersect(ray({-5, 0, 1}, {1, 0, 0}), 0, 100), 5 - std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(box.contains({1.3, 0, 1}));
  EXPECT_FALSE(box.contains({1.0, 1.0, 1}));
  EXPECT_NEAR(box.bounds().max.x(), std::sqrt(2.0), 1e-12);
}

TEST(ConvexSolid, RampTopSlopes) {
  // 10 m long along x from x=-5 (height 0) to x=5 (height 1): top z = 0.5 + x / 10.
  const auto ramp = ConvexSolid::ramp({0, 0}, 10, 2, 0.0, 0.0, 0.0, 1.0);
  for (const double x : {-4.0, 0.0, 2.5, 4.5}) {
    EXPECT_NEAR(*ramp.intersect(ray({x, 0, 5}, {0, 0, -1}), 0, 100), 5 - (0.5 + x / 10), 1e-12) << x;
  }
  EXPECT_TRUE(ramp.contains({4, 0, 0.85}));
  EXPECT_FALSE(ramp.contains({4, 0, 0.95}));
  EXPECT_DOUBLE_EQ(*ramp.intersect(ray({10, 0, 0.5}, {-1, 0, 0}), 0, 100), 5.0);  // the high end's face
}

TEST(Cylinder, SideAndCaps) {
  const Cylinder pole{{0, 0}, 0.5, 0.0, 3.0};
  EXPECT_DOUBLE_EQ(*pole.intersect(ray({-5, 0, 1}, {1, 0, 0}), 0, 100), 4.5);
  EXPECT_DOUBLE_EQ(*pole.intersect(ray({0.2, 0, 10}, {0, 0, -1}), 0, 100), 7.0);  // top cap
  EXPECT_FALSE(pole.intersect(ray({-5, 0, 3.5}, {1, 0, 0}), 0, 100));             // over it
  EXPECT_FALSE(pole.intersect(ray({-5, 0.6, 1}, {1, 0, 0}), 0, 100));             // beside it
  EXPECT_TRUE(pole.contains({0.4, 0, 2}));
}

TEST(Sphere, Distance) {
  const Sphere crown{{0, 0, 5}, 2.0};
  EXPECT_DOUBLE_EQ(*crown.intersect(ray({-10, 0, 5}, {1, 0, 0}), 0, 100), 8.0);
  EXPECT_FALSE(crown.intersect(ray({-10, 0, 7.5}, {1, 0, 0}), 0, 100));
}

TEST(HeightField, FlatAndSlopedTerrain) {
  // 11 x 11 vertices, 1 m apart from (0, 0); height = 0.2 * x (a plane, which bilinear cells reproduce).
  std::vector<double> heights;
  for (int j = 0; j <= 10; ++j) {
    for (int i = 0; i <= 10; ++i)
      heights.push_back(0.2 * i);
  }
  const HeightField terrain({0, 0}, 1.0, 11, 11, heights);
  EXPECT_NEAR(terrain.height(3.5, 7.2), 0.7, 1e-12);
  EXPECT_NEAR(*terrain.intersect(ray({3.5, 2.5, 10}, {0, 0, -1}), 0, 100), 10 - 0.7, 1e-9);
  // A horizontal ray at z = 1 runs into the slope where 0.2 x = 1: x = 5.
  EXPECT_NEAR(*terrain.intersect(ray({0.5, 5.3, 1.0}, {1, 0, 0}), 0, 100), 4.5, 1e-9);
  // A slanted ray, across many cells.
  const Ray slanted = ray({0.2, 0.3, 3.0}, {1, 0.7, -0.2});
  const double t = *terrain.intersect(slanted, 0, 100);
  const Eigen::Vector3d p = slanted.at(t);
  EXPECT_NEAR(p.z(), 0.2 * p.x(), 1e-9);
  EXPECT_FALSE(terrain.intersect(ray({0.5, 0.5, 5}, {0, 0, 1}), 0, 100));  // looking up
}

TEST(HeightField, RejectsBadInput) {
  EXPECT_THROW(HeightField({0, 0}, 1.0, 2, 2, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(HeightField({0, 0}, 0.0, 2, 2, {0, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(HeightField({0, 0}, 1.0, 2, 2, {0, 0, std::numeric_limits<double>::quiet_NaN(), 0}),
               std::invalid_argument);
}

}  // namespace
}  // namespace strata::sim

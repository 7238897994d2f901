#include "core/geometry/angles.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

TEST(WrapAngle, KeepsAnglesInsideTheRange) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(1.0), 1.0);
  EXPECT_DOUBLE_EQ(wrap_angle(-1.0), -1.0);
}

TEST(WrapAngle, WrapsFullTurns) {
  EXPECT_NEAR(wrap_angle(2.0 * kPi + 0.5), 0.5, 1e-12);
  EXPECT_NEAR(wrap_angle(-2.0 * kPi - 0.5), -0.5, 1e-12);
  EXPECT_NEAR(wrap_angle(7.0 * kPi), -kPi, 1e-9);
  EXPECT_NEAR(wrap_angle(kPi + 0.25), -kPi + 0.25, 1e-12);
}

TEST(WrapAngle, HalfOpenAtPi) {
  EXPECT_NEAR(wrap_angle(kPi), -kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(-kPi), -kPi, 1e-12);
}

}  // namespace
}  // namespace strata

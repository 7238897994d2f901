#include "server/control/teleop_freshness.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

constexpr double kNow = 5'000'000.0;  // ms on the server clock

TEST(TeleopFreshness, AFreshCommandInSequenceMovesTheRobot) {
  TeleopFreshness freshness;
  EXPECT_TRUE(freshness.admit(TeleopStamp{1, kNow - 40.0}, true, kNow).ok);
  EXPECT_TRUE(freshness.admit(TeleopStamp{2, kNow - 240.0}, true, kNow).ok);  // jitter within the bound
  EXPECT_TRUE(freshness.admit(TeleopStamp{7, kNow + 100.0}, true, kNow).ok);  // a gap in seq is fine
}

TEST(TeleopFreshness, ACommandHeldBackByAnOutageIsStale) {
  TeleopFreshness freshness;
  const auto late = freshness.admit(TeleopStamp{1, kNow - 3000.0}, true, kNow);
  EXPECT_FALSE(late.ok);
  EXPECT_EQ(late.code, ErrorCode::kStaleCommand);
  EXPECT_EQ(freshness.admit(TeleopStamp{2, kNow - 251.0}, true, kNow).code, ErrorCode::kStaleCommand);
  // A refused command leaves the sequence where it was: the next fresh one is taken.
  EXPECT_TRUE(freshness.admit(TeleopStamp{3, kNow}, true, kNow).ok);
}

TEST(TeleopFreshness, ACommandOvertakenOrRepeatedIsRefused) {
  TeleopFreshness freshness;
  ASSERT_TRUE(freshness.admit(TeleopStamp{5, kNow}, true, kNow).ok);
  EXPECT_EQ(freshness.admit(TeleopStamp{4, kNow}, true, kNow).code, ErrorCode::kStaleCommand);
  EXPECT_EQ(freshness.admit(TeleopStamp{5, kNow}, true, kNow).code, ErrorCode::kStaleCommand);
}

TEST(TeleopFreshness, AClockFarAheadIsRefused) {
  TeleopFreshness freshness;
  EXPECT_EQ(freshness.admit(TeleopStamp{1, kNow + 1000.0}, true, kNow).code, ErrorCode::kStaleCommand);
}

TEST(TeleopFreshness, AMovingCommandWithoutItsStampIsRefusedAStopNever) {
  TeleopFreshness freshness;
  EXPECT_EQ(freshness.admit(std::nullopt, true, kNow).code, ErrorCode::kBadParams);
  EXPECT_TRUE(freshness.admit(std::nullopt, false, kNow).ok);
  ASSERT_TRUE(freshness.admit(TeleopStamp{9, kNow}, true, kNow).ok);
  EXPECT_TRUE(freshness.admit(TeleopStamp{3, kNow - 60'000.0}, false, kNow).ok) << "a stop is always obeyed";
}

}  // namespace
}  // namespace strata

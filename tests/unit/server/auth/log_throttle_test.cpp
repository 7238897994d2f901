// What a client can put into the log: throttled and cut to one short printable line (issue 59 item 7).
#include "server/auth/log_throttle.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

namespace strata::auth {
namespace {

TEST(LogThrottle, ABurstThenOneASecondAndTheNextSaysHowManyWereHeldBack) {
  LogThrottle throttle(1.0, 3.0);
  const LogThrottle::Clock::time_point start{std::chrono::seconds(100)};
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(throttle.admit(start), 0U) << i;
  for (int i = 0; i < 500; ++i)
    EXPECT_FALSE(throttle.admit(start + std::chrono::milliseconds(i)));
  EXPECT_EQ(throttle.admit(start + std::chrono::milliseconds(1000)), 500U);
  EXPECT_FALSE(throttle.admit(start + std::chrono::milliseconds(1001)));
  EXPECT_EQ(throttle.admit(start + std::chrono::milliseconds(2001)), 1U);
  EXPECT_EQ(held_back(0), "");
  EXPECT_EQ(held_back(500), " (500 more like it not logged)");
}

TEST(Loggable, ClientTextIsCutAndOnlyPrintable) {
  EXPECT_EQ(loggable("https://kiosk.example"), "https://kiosk.example");
  EXPECT_EQ(loggable("a\nforged line\x1b[31m\xff"), "a?forged line?[31m?");
  const std::string long_origin = "https://" + std::string(10'000, 'a');
  const std::string cut = loggable(long_origin);
  EXPECT_EQ(cut, "https://" + std::string(72, 'a') + "... (10008 bytes)");
}

}  // namespace
}  // namespace strata::auth

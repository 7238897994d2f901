#include "server/net/rate_limiter.hpp"

#include <gtest/gtest.h>

namespace strata::net {
namespace {

TEST(RateLimiter, AllowsABurstThenTheRate) {
  RateLimiter limiter(10.0, 5.0);
  RateLimiter::Clock::time_point now{std::chrono::seconds(100)};
  int allowed = 0;
  for (int i = 0; i < 20; ++i)
    allowed += limiter.allow(now) ? 1 : 0;
  EXPECT_EQ(allowed, 5);                  // the burst, all at one instant
  now += std::chrono::milliseconds(500);  // half a second at 10/s refills 5
  allowed = 0;
  for (int i = 0; i < 20; ++i)
    allowed += limiter.allow(now) ? 1 : 0;
  EXPECT_EQ(allowed, 5);
  now += std::chrono::seconds(60);  // never more than the burst
  allowed = 0;
  for (int i = 0; i < 20; ++i)
    allowed += limiter.allow(now) ? 1 : 0;
  EXPECT_EQ(allowed, 5);
}

}  // namespace
}  // namespace strata::net

#include "server/net/connection_limit.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace strata::net {
namespace {

TEST(ConnectionLimit, RefusesOverTheLimitAndFreesOnDestruction) {
  ConnectionLimit limit(2);
  auto first = limit.try_acquire();
  auto second = limit.try_acquire();
  ASSERT_TRUE(first && second);
  EXPECT_FALSE(limit.try_acquire());
  EXPECT_EQ(limit.in_use(), 2u);
  {
    const ConnectionLimit::Slot moved = std::move(*first);  // a moved-from slot gives nothing back
    first.reset();
    EXPECT_EQ(limit.in_use(), 2u);
  }
  EXPECT_EQ(limit.in_use(), 1u);
  EXPECT_TRUE(limit.try_acquire());  // acquired and given back at once
  EXPECT_EQ(limit.in_use(), 1u);
}

TEST(ConnectionLimit, ConcurrentAcquiresNeverExceedTheLimit) {
  ConnectionLimit limit(3);
  std::atomic<int> holding{0};
  std::atomic<int> most{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 2000; ++i) {
        if (auto slot = limit.try_acquire()) {
          const int now = holding.fetch_add(1) + 1;
          int seen = most.load();
          while (now > seen && !most.compare_exchange_weak(seen, now)) {
          }
          holding.fetch_sub(1);
        }
      }
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_LE(most.load(), 3);
  EXPECT_EQ(limit.in_use(), 0u);
}

}  // namespace
}  // namespace strata::net

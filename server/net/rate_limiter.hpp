#pragma once

#include <algorithm>
#include <chrono>

namespace strata::net {

/// A token bucket: `rate` messages per second on average, bursts of up to `burst`. Each client has one, so
/// a client that floods gets `rate_limited` errors and nobody else notices. Not thread-safe (lives on the
/// session's strand). Time is passed in so tests need no clock.
class RateLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  RateLimiter(double rate, double burst) : rate_(rate), burst_(burst), tokens_(burst) {}

  /// Takes one token if there is one.
  bool allow(Clock::time_point now) {
    if (last_ != Clock::time_point{}) {
      const double elapsed = std::chrono::duration<double>(now - last_).count();
      tokens_ = std::min(burst_, tokens_ + std::max(0.0, elapsed) * rate_);
    }
    last_ = now;
    if (tokens_ < 1.0)
      return false;
    tokens_ -= 1.0;
    return true;
  }

 private:
  double rate_;
  double burst_;
  double tokens_;
  Clock::time_point last_{};
};

}  // namespace strata::net

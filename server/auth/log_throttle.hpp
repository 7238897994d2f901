#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace strata::auth {

/// Whatever a client can make the server log goes through one of these, one per kind of message: bursts
/// of up to `burst`, `rate` a second after, the rest counted, and the next message let through says how
/// many were held back. A refused Origin was logged whole, unthrottled: 80 MB in 2.5 s (issue 59 item 7).
/// Thread-safe: the io threads share them.
class LogThrottle {
 public:
  using Clock = std::chrono::steady_clock;

  explicit LogThrottle(double rate = 1.0, double burst = 10.0) : rate_(rate), burst_(burst), tokens_(burst) {}

  /// Whether to log one more now; if so, how many were held back since the last one let through.
  [[nodiscard]] std::optional<std::size_t> admit(Clock::time_point now = Clock::now()) {
    std::lock_guard lock(mutex_);
    if (last_ != Clock::time_point{})  // a token bucket, as RateLimiter's
      tokens_ = std::min(burst_,
                         tokens_ + std::max(0.0, std::chrono::duration<double>(now - last_).count()) * rate_);
    last_ = now;
    if (tokens_ < 1.0) {
      ++held_back_;
      return std::nullopt;
    }
    tokens_ -= 1.0;
    return std::exchange(held_back_, 0);
  }

 private:
  std::mutex mutex_;
  double rate_;
  double burst_;
  double tokens_;
  Clock::time_point last_{};
  std::size_t held_back_ = 0;
};

/// " (N more like it not logged)", or nothing: for the message a LogThrottle let through.
[[nodiscard]] inline std::string held_back(std::size_t messages) {
  return messages == 0 ? std::string() : " (" + std::to_string(messages) + " more like it not logged)";
}

/// Text a client sent, fit for one log line: at most `max` bytes of it, anything but printable ASCII as
/// '?', and how long it was when cut.
[[nodiscard]] inline std::string loggable(std::string_view text, std::size_t max = 80) {
  std::string out;
  out.reserve(std::min(text.size(), max) + 24);
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out.push_back(c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?');
  }
  if (text.size() > max)
    out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace strata::auth

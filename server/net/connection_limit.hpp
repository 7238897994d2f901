#pragma once

#include <atomic>
#include <cstddef>
#include <optional>

namespace strata::net {

/// At most `max` of something at once (WebSocket clients): a session holds a Slot for as long as it lives,
/// and one more is refused while all are taken. Thread-safe; a Slot must not outlive its limit.
class ConnectionLimit {
 public:
  /// One place, given back when destroyed.
  class Slot {
   public:
    Slot(Slot&& other) noexcept : limit_(other.limit_) { other.limit_ = nullptr; }
    Slot& operator=(Slot&&) = delete;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    ~Slot() {
      if (limit_ != nullptr)
        limit_->in_use_.fetch_sub(1, std::memory_order_acq_rel);
    }

   private:
    friend class ConnectionLimit;
    explicit Slot(ConnectionLimit* limit) : limit_(limit) {}
    ConnectionLimit* limit_;
  };

  explicit ConnectionLimit(std::size_t max) : max_(max) {}
  ConnectionLimit(const ConnectionLimit&) = delete;
  ConnectionLimit& operator=(const ConnectionLimit&) = delete;

  /// A place, or nullopt when all `max` are taken.
  [[nodiscard]] std::optional<Slot> try_acquire() {
    std::size_t current = in_use_.load(std::memory_order_acquire);
    do {
      if (current >= max_)
        return std::nullopt;
    } while (!in_use_.compare_exchange_weak(current, current + 1, std::memory_order_acq_rel));
    return Slot(this);
  }

  [[nodiscard]] std::size_t max() const { return max_; }
  [[nodiscard]] std::size_t in_use() const { return in_use_.load(std::memory_order_acquire); }

 private:
  std::size_t max_;
  std::atomic<std::size_t> in_use_{0};
};

}  // namespace strata::net

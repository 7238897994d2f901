#pragma once

#include <algorithm>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "server/net/outgoing_message.hpp"

namespace strata::net {

/// A client's outgoing queue: bounded, with coalescing. Beast allows one write in flight per stream,
/// so the session writes `front()` and calls `pop()` when that write completes. Not thread-safe: it
/// lives on the session's strand.
class SendQueue {
 public:
  explicit SendQueue(std::size_t capacity) : capacity_(capacity) {}

  enum class PushResult { kQueued, kCoalesced, kStale, kOverflow };

  /// Queues `message`, replacing an unsent message with the same coalesce key in place. The message
  /// being written (the front, once `writing()`) is never replaced. kStale: a coalescing message with an
  /// order not after the last one queued for its key, dropped. kOverflow: the queue is full of messages
  /// that cannot be dropped; the client is not keeping up.
  PushResult push(OutgoingMessage message) {
    if (!message.coalesce_key.empty()) {
      // A stream only moves forward: drop what is not newer than the last message queued for the key.
      auto last = std::find_if(last_order_.begin(), last_order_.end(),
                               [&](const auto& entry) { return entry.first == message.coalesce_key; });
      if (last == last_order_.end()) {
        last_order_.emplace_back(message.coalesce_key, message.order);
      } else if (message.order <= last->second && message.order != 0.0) {
        return PushResult::kStale;
      } else {
        last->second = message.order;
      }
      const std::size_t first_unsent = writing_ ? 1 : 0;
      for (std::size_t i = first_unsent; i < queue_.size(); ++i) {
        if (queue_[i].coalesce_key == message.coalesce_key) {
          queue_[i] = std::move(message);
          return PushResult::kCoalesced;
        }
      }
    }
    if (queue_.size() >= capacity_)
      return PushResult::kOverflow;
    queue_.push_back(std::move(message));
    return PushResult::kQueued;
  }

  /// The next message to write, marking it in flight; nullptr when empty or a write is in flight.
  const OutgoingMessage* start_write() {
    if (writing_ || queue_.empty())
      return nullptr;
    writing_ = true;
    return &queue_.front();
  }
  /// The write of the front message completed.
  void finish_write() {
    if (!writing_)
      return;
    writing_ = false;
    queue_.pop_front();
  }

  [[nodiscard]] bool writing() const { return writing_; }
  [[nodiscard]] std::size_t size() const { return queue_.size(); }

 private:
  std::size_t capacity_;
  std::deque<OutgoingMessage> queue_;
  std::vector<std::pair<std::string, double>> last_order_;  // per coalesce key; a handful of keys at most
  bool writing_ = false;
};

}  // namespace strata::net

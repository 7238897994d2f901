#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include "server/streams/outgoing_message.hpp"

namespace strata::net {

/// A client's outgoing queue: bounded, with coalescing. Beast allows one write in flight per stream,
/// so the session writes `front()` and calls `pop()` when that write completes. Not thread-safe: it
/// lives on the session's strand.
///
/// Bounds: coalescing messages (pose, each tile, the occupancy image, ...) hold at most one unsent entry
/// per key, so they are bounded by the number of keys (the map's tiles), and their payloads are shared by
/// all clients. `capacity` bounds the others (replies, errors): a client that lets those pile up is not
/// reading, and is dropped.
class SendQueue {
 public:
  explicit SendQueue(std::size_t capacity) : capacity_(capacity) {}

  enum class PushResult { kQueued, kCoalesced, kStale, kOverflow };

  /// Queues `message`, replacing an unsent message with the same coalesce key in place. The message
  /// being written (the front, once `writing()`) is never replaced. kStale: a coalescing message with an
  /// order not after the last one queued for its key, dropped. kOverflow: too many messages that cannot
  /// be dropped are waiting; the client is not keeping up.
  PushResult push(streams::OutgoingMessage message) {
    if (message.coalesce_key.empty()) {
      if (plain_ >= capacity_)
        return PushResult::kOverflow;
      ++plain_;
      queue_.push_back(std::move(message));
      return PushResult::kQueued;
    }
    // A stream only moves forward: drop what is not newer than the last message queued for the key.
    auto [key, inserted] = keys_.try_emplace(message.coalesce_key);
    if (!inserted && message.order && key->second.order && *message.order <= *key->second.order)
      return PushResult::kStale;
    key->second.order = message.order;
    if (!inserted && key->second.queued && key->second.position >= first_unsent_position()) {
      queue_[key->second.position - popped_] = std::move(message);
      return PushResult::kCoalesced;
    }
    key->second.queued = true;
    key->second.position = popped_ + queue_.size();
    queue_.push_back(std::move(message));
    return PushResult::kQueued;
  }

  /// The next message to write, marking it in flight; nullptr when empty or a write is in flight.
  const streams::OutgoingMessage* start_write() {
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
    streams::OutgoingMessage& front = queue_.front();
    if (front.coalesce_key.empty()) {
      --plain_;
    } else if (auto key = keys_.find(front.coalesce_key);
               key != keys_.end() && key->second.position == popped_) {
      key->second.queued = false;
    }
    queue_.pop_front();
    ++popped_;
  }

  [[nodiscard]] bool writing() const { return writing_; }
  [[nodiscard]] std::size_t size() const { return queue_.size(); }
  /// Bytes of payload waiting (shared payloads counted once per queue), for metrics and tests.
  [[nodiscard]] std::size_t bytes() const {
    std::size_t total = 0;
    for (const auto& message : queue_)
      total += message.payload ? message.payload->size() : 0;
    return total;
  }

 private:
  struct KeyState {
    std::optional<double> order;  // of the last message queued under the key
    bool queued = false;          // an entry for the key is in the queue
    std::uint64_t position = 0;   // its absolute position (popped_ + index) when queued
  };
  [[nodiscard]] std::uint64_t first_unsent_position() const { return popped_ + (writing_ ? 1 : 0); }

  std::size_t capacity_;
  std::deque<streams::OutgoingMessage> queue_;
  std::unordered_map<std::string, KeyState> keys_;
  std::uint64_t popped_ = 0;  // messages written and removed so far: absolute position of the front
  std::size_t plain_ = 0;     // queued messages without a coalesce key
  bool writing_ = false;
};

}  // namespace strata::net

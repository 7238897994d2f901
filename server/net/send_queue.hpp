#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <variant>

#include "server/streams/outgoing_message.hpp"

namespace strata::net {

/// A client's outgoing queue: bounded, with coalescing, in two lanes. Beast allows one write in flight per
/// stream, so the session writes what `start_write()` gives and calls `finish_write()` when that write
/// completes. Not thread-safe: it lives on the session's strand.
///
/// Lanes: the next write is the oldest prompt message (pose, status, goal, replies) if there is one, else
/// the oldest bulk one (map tiles, the occupancy image). A map that streams to a late joiner or after a
/// rebuild therefore holds the pose back by one tile at most, over any link.
///
/// Bounds: coalescing messages (pose, each tile, the occupancy image, ...) hold at most one unsent entry
/// per key, so they are bounded by the number of keys (the map's tiles), and their payloads are shared by
/// all clients. `capacity` bounds the others (replies, errors): a client that lets those pile up is not
/// reading, and is dropped.
class SendQueue {
 public:
  explicit SendQueue(std::size_t capacity) : capacity_(capacity) {}

  enum class PushResult { kQueued, kCoalesced, kStale, kOverflow };

  /// Queues `message`, replacing an unsent message with the same coalesce key in its place. The message
  /// being written is never replaced. kStale: a coalescing message with an order not after the last one
  /// queued for its key, dropped. kOverflow: too many messages that cannot be dropped are waiting; the
  /// client is not keeping up.
  PushResult push(streams::OutgoingMessage message);

  /// The next message to write, marking it in flight; nullptr when empty or a write is in flight.
  const streams::OutgoingMessage* start_write();
  /// The write of the message in flight completed.
  void finish_write();

  [[nodiscard]] bool writing() const { return in_flight_.has_value(); }
  /// The message being written; nullptr when none is.
  [[nodiscard]] const streams::OutgoingMessage* in_flight() const {
    return in_flight_ ? &*in_flight_ : nullptr;
  }
  /// Messages waiting, the one being written included.
  [[nodiscard]] std::size_t size() const { return unsent_ + (writing() ? 1 : 0); }
  /// Payload bytes waiting, the one being written included (shared payloads count once per queue).
  [[nodiscard]] std::size_t bytes() const { return bytes_; }
  /// Messages replaced by a newer one of their key before they were written: what a lagging client did
  /// not get.
  [[nodiscard]] std::uint64_t superseded() const { return superseded_; }

 private:
  /// A lane holds plain messages themselves and coalescing ones by key (the message waits in its key).
  using Entry = std::variant<streams::OutgoingMessage, std::string>;
  struct KeyState {
    std::optional<double> order;                     // of the last message queued under the key
    std::optional<streams::OutgoingMessage> unsent;  // waiting in its lane, not yet written
  };
  static std::size_t size_of(const streams::OutgoingMessage& message) {
    return message.payload ? message.payload->size() : 0;
  }
  std::deque<Entry>& lane_of(const streams::OutgoingMessage& message) {
    return lanes_[static_cast<std::size_t>(message.lane)];
  }

  std::size_t capacity_;
  std::array<std::deque<Entry>, 2> lanes_;  // indexed by OutgoingMessage::Lane, prompt first
  std::unordered_map<std::string, KeyState> keys_;
  std::optional<streams::OutgoingMessage> in_flight_;
  std::size_t unsent_ = 0;  // entries in the lanes
  std::size_t plain_ = 0;   // queued messages without a coalesce key, the one in flight included
  std::size_t bytes_ = 0;
  std::uint64_t superseded_ = 0;
};

}  // namespace strata::net

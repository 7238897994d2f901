#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace strata::streams {

/// One message on its way to clients. The payload is encoded once and shared by every client's queue.
struct OutgoingMessage {
  /// Which of a client's queues it waits in. Prompt messages (pose, status, goal, replies) are written
  /// before any bulk one (map tiles, the occupancy image), so a map that streams over a slow link never
  /// holds the pose back by more than the one bulk message being written.
  enum class Lane : std::uint8_t { kPrompt, kBulk };

  std::shared_ptr<const std::string> payload;
  bool binary = false;
  /// Messages with the same non-empty key supersede each other while unsent: a client that lags
  /// gets the newest pose, not a backlog of stale ones.
  std::string coalesce_key;
  /// For coalesced streams: where the message stands in its stream (a pose's stamp, a tile's version). A
  /// client's queue drops one that is not newer than the last it queued, so a stream never goes backwards
  /// or repeats, even when the late joiner's snapshot and the next broadcast carry the same data.
  /// Empty: unordered, each one supersedes the last (status). A pose stamped 0 (the simulator's first) is
  /// ordered like any other, which is why this is not a sentinel value.
  std::optional<double> order;
  /// The stream it belongs to (protocol::Stream bit); a client gets it only when subscribed. 0: always.
  std::uint8_t stream = 0;
  Lane lane = Lane::kPrompt;
  /// When it was made: a client's queue reports how old the pose it last wrote was (/metrics).
  std::chrono::steady_clock::time_point made = std::chrono::steady_clock::now();

  static OutgoingMessage text(std::string body, std::string coalesce_key = {},
                              std::optional<double> order = std::nullopt, std::uint8_t stream = 0) {
    return {std::make_shared<const std::string>(std::move(body)), false, std::move(coalesce_key), order,
            stream};
  }
  /// Map data: binary, and in the bulk lane.
  static OutgoingMessage map_frame(std::string body, std::string coalesce_key, std::optional<double> order,
                                   std::uint8_t stream) {
    return {std::make_shared<const std::string>(std::move(body)),
            true,
            std::move(coalesce_key),
            order,
            stream,
            Lane::kBulk};
  }
};

}  // namespace strata::streams

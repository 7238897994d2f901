#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <vector>

#include "server/streams/outgoing_message.hpp"

namespace strata::streams {

/// How one client is keeping up, for /metrics: what waits for it, and how old its pose is.
struct ClientStats {
  std::uint64_t id = 0;  ///< the connection's number since the server started
  bool operator_role = false;
  std::size_t queued_bytes = 0;  ///< in its send queue, the message being written included
  std::size_t socket_bytes = 0;  ///< written to its socket and not yet acknowledged by the client
  std::uint64_t superseded = 0;  ///< messages a newer one replaced before they were written
  /// How old the last pose written to it was when the write completed; empty before the first.
  std::optional<double> pose_age_s;
};

/// A connected client as the hub sees it: something that takes messages without blocking.
class ClientConnection {
 public:
  virtual ~ClientConnection() = default;
  /// Must return at once (queue and hand off to the client's own strand).
  virtual void send(OutgoingMessage message) = 0;
  /// Must return at once; any thread.
  [[nodiscard]] virtual ClientStats stats() const = 0;
};

/// The shared state of all WebSocket clients: who is connected, and fan-out to them. Thread-safe.
/// A client's queue and writes are its own; broadcasting only hands each client a shared payload.
class ClientHub {
 public:
  void join(const std::shared_ptr<ClientConnection>& client);
  void leave(const ClientConnection* client);
  void broadcast(const OutgoingMessage& message);
  [[nodiscard]] std::size_t size() const;
  /// Every connected client's stats, in the order they connected.
  [[nodiscard]] std::vector<ClientStats> stats() const;

 private:
  mutable std::mutex mutex_;
  std::unordered_map<const ClientConnection*, std::weak_ptr<ClientConnection>> clients_;
};

}  // namespace strata::streams

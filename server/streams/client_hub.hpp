#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "server/streams/outgoing_message.hpp"

namespace strata::streams {

/// A connected client as the hub sees it: something that takes messages without blocking.
class ClientConnection {
 public:
  virtual ~ClientConnection() = default;
  /// Must return at once (queue and hand off to the client's own strand).
  virtual void send(OutgoingMessage message) = 0;
};

/// The shared state of all WebSocket clients: who is connected, and fan-out to them. Thread-safe.
/// A client's queue and writes are its own; broadcasting only hands each client a shared payload.
class ClientHub {
 public:
  void join(const std::shared_ptr<ClientConnection>& client);
  void leave(const ClientConnection* client);
  void broadcast(const OutgoingMessage& message);
  [[nodiscard]] std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::unordered_map<const ClientConnection*, std::weak_ptr<ClientConnection>> clients_;
};

}  // namespace strata::streams

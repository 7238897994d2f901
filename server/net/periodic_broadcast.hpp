#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "server/streams/client_hub.hpp"

namespace strata::net {

/// Broadcasts a message to every WebSocket client at a fixed rate, decoupled from the rate at which the
/// robot's state changes: the pose stream (20-50 Hz), the status stream (1 Hz), the map and navigation
/// streams. Each message is
/// encoded once and shared by all clients' queues; nothing is sent when the encoder has nothing new.
class PeriodicBroadcast : public std::enable_shared_from_this<PeriodicBroadcast> {
 public:
  /// Returns the messages to send now (none when nothing is new).
  using Encoder = std::function<std::vector<streams::OutgoingMessage>()>;

  PeriodicBroadcast(boost::asio::io_context& io, streams::ClientHub& hub, double rate_hz, Encoder encoder);

  void start();
  void stop();

 private:
  void schedule();

  boost::asio::steady_timer timer_;
  streams::ClientHub& hub_;
  std::chrono::steady_clock::duration period_;
  Encoder encoder_;
  bool running_ = false;
};

}  // namespace strata::net

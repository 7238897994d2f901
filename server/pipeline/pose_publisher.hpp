#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>

#include "server/net/client_hub.hpp"
#include "server/state/robot_state.hpp"

namespace strata::pipeline {

/// Streams the newest pose to every WebSocket client at a fixed rate, decoupled from the rate at
/// which drivers produce poses. Each pose is encoded once and shared by all clients' queues.
class PosePublisher : public std::enable_shared_from_this<PosePublisher> {
 public:
  PosePublisher(boost::asio::io_context& io, const RobotState& robot, net::ClientHub& hub, double rate_hz);

  void start();
  void stop();

 private:
  void schedule();
  void publish();

  boost::asio::steady_timer timer_;
  const RobotState& robot_;
  net::ClientHub& hub_;
  std::chrono::steady_clock::duration period_;
  double last_stamp_ = -1.0;
  bool running_ = false;
};

}  // namespace strata::pipeline

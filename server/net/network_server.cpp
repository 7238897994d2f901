#include "server/net/network_server.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <csignal>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "server/net/tls_context.hpp"
#include "server/protocol/client_messages.hpp"
#include "server/protocol/messages.hpp"

namespace strata::net {
namespace {

std::shared_ptr<boost::asio::ssl::context> load_tls(const NetworkOptions& options) {
  if (options.tls_certificate.empty() && options.tls_key.empty())
    return nullptr;
  if (options.tls_certificate.empty() || options.tls_key.empty())
    throw std::runtime_error("TLS needs both --tls-cert and --tls-key");
  return make_tls_context(options.tls_certificate, options.tls_key);
}

std::uint8_t stream_bit(protocol::Stream stream) {
  return static_cast<std::uint8_t>(stream);
}

}  // namespace

NetworkServer::NetworkServer(ServerServices services)
    : io_(services.network.io_threads),
      tls_(load_tls(services.network)),
      context_(std::make_shared<ServerContext>(std::move(services))),
      map_strand_(boost::asio::make_strand(io_)),
      signals_(io_, SIGINT, SIGTERM) {
  const NetworkOptions& options = context_->services.network;
  const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(options.bind_address),
                                                options.port);
  try {
    listener_ = std::make_shared<Listener>(io_, endpoint, context_, tls_);
  } catch (const boost::system::system_error& error) {
    throw std::runtime_error("cannot listen on " + options.bind_address + ":" + std::to_string(options.port) +
                             ": " + error.code().message());
  }
  // The pose: only when there is a new one, a new sample or a new correction. A lidar alone's correction
  // comes after the sample of its scan went out: sent on the sample alone, every pose showed the scan
  // before, and the last scan's never.
  add_broadcast(options.pose_rate,
                [robot = context_->services.robot, last_version = std::optional<std::uint64_t>()]() mutable {
                  std::vector<streams::OutgoingMessage> messages;
                  const auto snapshot = robot->snapshot();
                  if (!snapshot || snapshot->version == last_version)
                    return messages;
                  last_version = snapshot->version;
                  messages.push_back(streams::OutgoingMessage::text(protocol::pose_message(*snapshot), "pose",
                                                                    static_cast<double>(snapshot->version),
                                                                    stream_bit(protocol::Stream::kPose)));
                  return messages;
                });
  add_broadcast(1.0, [status = &context_->status] {
    return std::vector{streams::OutgoingMessage::text(status->poll(), "status", std::nullopt,
                                                      stream_bit(protocol::Stream::kStatus))};
  });
  if (context_->navigation_stream)
    add_broadcast(20.0, [stream = context_->navigation_stream.get()] { return stream->poll(); });
  if (!options.fleet.broker.empty())
    fleet_ = std::make_shared<fleet::VdaVehicle>(io_, context_->services);  // a bad URL stops the start
}

// The broadcasts' pending timers go with the io_context, which is destroyed last.
NetworkServer::~NetworkServer() = default;

void NetworkServer::add_broadcast(double rate_hz, PeriodicBroadcast::Encoder encoder) {
  broadcasts_.push_back(std::make_shared<PeriodicBroadcast>(io_, context_->hub, rate_hz, std::move(encoder)));
}

std::function<void()> NetworkServer::map_publisher() {
  if (!context_->map_stream)
    return {};
  // References only: destroying the callback must not touch the io_context.
  return [strand = &map_strand_, context = context_.get()] {
    boost::asio::post(*strand, [context] {
      for (const auto& message : context->map_stream->poll())
        context->hub.broadcast(message);
    });
  };
}

void NetworkServer::start() {
  signals_.async_wait([this](const boost::system::error_code& error, int signal) {
    if (error)
      return;
    spdlog::info("signal {}: shutting down", signal);
    io_.stop();
  });
  listener_->run();
  for (const auto& broadcast : broadcasts_)
    broadcast->start();
  if (fleet_)
    fleet_->start();
}

void NetworkServer::run() {
  std::vector<std::thread> threads;
  for (int i = 1; i < context_->services.network.io_threads; ++i)
    threads.emplace_back([this] { io_.run(); });
  io_.run();
  for (auto& thread : threads)
    thread.join();
  if (fleet_)
    fleet_->close();  // connection OFFLINE, on this thread now that the loop has stopped
  // A download, save or load under way finishes before the robot's pipeline stops; its answer is not sent.
  context_->map_work.join();
}

}  // namespace strata::net

#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/strand.hpp>
#include <functional>
#include <memory>
#include <vector>

#include "server/control/server_services.hpp"
#include "server/fleet/vda_vehicle.hpp"
#include "server/net/listener.hpp"
#include "server/net/periodic_broadcast.hpp"
#include "server/net/server_context.hpp"

namespace strata::net {

/// Everything on the network side of one server: the io_context and its threads, the listener, the shared
/// ServerContext (client hub, streams, router) and the broadcasts that feed the streams: the pose at
/// NetworkOptions::pose_rate, the status at 1 Hz, goal and path at 20 Hz, and the map pushed by the mapping
/// thread as soon as it publishes; and with --vda5050, the robot as a VDA 5050 vehicle to a fleet master
/// over MQTT on the same event loop. Runs until SIGINT or SIGTERM.
class NetworkServer {
 public:
  /// Loads the TLS certificate and key and binds the port at once, so a bad file, a bad address or a port
  /// in use fails here with a clear error. `services.network` as the server runs with it (token and hosts
  /// complete); the pointers must outlive this object.
  explicit NetworkServer(ServerServices services);
  ~NetworkServer();
  NetworkServer(const NetworkServer&) = delete;
  NetworkServer& operator=(const NetworkServer&) = delete;

  /// For the mapping thread (RobotPipeline::on_map_published): posts one broadcast of what changed onto
  /// one strand, so map frames go out in order. Holds references only: whoever calls it must stop before
  /// this object goes.
  [[nodiscard]] std::function<void()> map_publisher();

  /// Starts accepting and broadcasting, and catches SIGINT and SIGTERM.
  void start();
  /// Serves on NetworkOptions::io_threads threads (this one included) until a signal; then returns.
  void run();

  [[nodiscard]] boost::asio::ip::tcp::endpoint local_endpoint() const { return listener_->local_endpoint(); }
  [[nodiscard]] bool tls() const { return tls_ != nullptr; }

 private:
  void add_broadcast(double rate_hz, PeriodicBroadcast::Encoder encoder);

  boost::asio::io_context io_;
  std::shared_ptr<boost::asio::ssl::context> tls_;  // null: plain HTTP
  std::shared_ptr<ServerContext> context_;
  std::shared_ptr<Listener> listener_;
  boost::asio::strand<boost::asio::io_context::executor_type> map_strand_;
  std::vector<std::shared_ptr<PeriodicBroadcast>> broadcasts_;
  std::shared_ptr<fleet::VdaVehicle> fleet_;  // null: no --vda5050
  boost::asio::signal_set signals_;
};

}  // namespace strata::net

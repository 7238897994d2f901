#pragma once

#include <boost/asio/thread_pool.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "drivers/sim/world/world.hpp"
#include "server/api/http_router.hpp"
#include "server/auth/operator_token.hpp"
#include "server/control/robot_commands.hpp"
#include "server/control/server_services.hpp"
#include "server/net/address_limit.hpp"
#include "server/net/connection_limit.hpp"
#include "server/protocol/messages.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"
#include "server/streams/client_hub.hpp"
#include "server/streams/map_stream.hpp"
#include "server/streams/navigation_stream.hpp"
#include "server/streams/outgoing_message.hpp"
#include "server/streams/server_metrics.hpp"
#include "server/streams/status_stream.hpp"

namespace strata::net {

/// What every session shares: the robot's services, the connected clients, the streams' current state
/// and the request router.
struct ServerContext {
  explicit ServerContext(ServerServices services_in)
      : services(std::move(services_in)),
        sim_world_message(services.sim_world ? protocol::sim_world_message(*services.sim_world)
                                             : std::string()),
        websocket_clients(services.network.max_clients),
        http_connections(services.network.max_http_connections),
        connections_per_address(services.network.max_connections_per_address),
        status(*services.robot, services.map, hub),
        map_stream(services.map ? std::make_unique<streams::MapStream>(*services.map) : nullptr),
        navigation_stream(services.motion ? std::make_unique<streams::NavigationStream>(*services.motion)
                                          : nullptr),
        router(services, hub, status, metrics) {}

  /// The current goal, path, occupancy and tiles: what a late joiner gets after hello, status and pose.
  [[nodiscard]] std::vector<streams::OutgoingMessage> current_state() const {
    std::vector<streams::OutgoingMessage> messages;
    if (navigation_stream)
      messages = navigation_stream->current();
    if (map_stream) {
      auto frames = map_stream->current();
      messages.insert(messages.end(), std::make_move_iterator(frames.begin()),
                      std::make_move_iterator(frames.end()));
    }
    return messages;
  }

  ServerServices services;
  std::string sim_world_message;  ///< sent to every client on connect; empty for a real robot
  streams::ClientHub hub;
  ConnectionLimit websocket_clients;  ///< a WebSocket session holds a slot from the upgrade to its end
  /// A connection holds a slot from its accept until it closes or is upgraded to a WebSocket (then it
  /// counts as a WebSocket client only).
  ConnectionLimit http_connections;
  AddressLimit connections_per_address;  ///< every connection, from its accept until it closes
  /// Places for operators (the right token) beyond max-clients: viewers cannot lock the operator out.
  ConnectionLimit operator_reserve{kOperatorReserve};
  static constexpr std::size_t kOperatorReserve = 4;

  /// A WebSocket place for a client of `role`: one of max-clients, or for an operator when those are all
  /// taken, one of the reserve.
  [[nodiscard]] std::optional<ConnectionLimit::Slot> websocket_place(auth::Role role) {
    if (auto slot = websocket_clients.try_acquire())
      return slot;
    if (role == auth::Role::kOperator)
      return operator_reserve.try_acquire();
    return std::nullopt;
  }
  streams::ServerMetrics metrics;
  streams::StatusStream status;
  std::unique_ptr<streams::MapStream> map_stream;
  std::unique_ptr<streams::NavigationStream> navigation_stream;
  api::HttpRouter router;
  /// Requests that work on the whole map (HttpRouter::works_on_the_whole_map) run here, off the network
  /// threads, and at most kMapWork of them wait or run at once: eight clients downloading the map must not
  /// stall /healthz or the streams (issue 59 item 10). Last member: joined first, while the rest still
  /// exists.
  static constexpr std::size_t kMapWork = 4;
  /// What a request over that bound is told (REST 503 and the WebSocket's `unavailable` alike).
  static std::string map_work_busy() {
    return "the server is busy with " + std::to_string(kMapWork) +
           " map downloads, saves or loads; try again in a few seconds";
  }
  ConnectionLimit map_work_places{kMapWork};
  boost::asio::thread_pool map_work{1};
};

}  // namespace strata::net

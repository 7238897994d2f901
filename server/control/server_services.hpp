#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "drivers/sim/world/world.hpp"
#include "server/control/robot_commands.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata {

/// The parts of the running robot the network side reaches: state to read and commands to give. Any
/// pointer may be null (a unit test, a server without a navigator); the features that need it answer
/// `unavailable`.
struct ServerServices {
  const RobotState* robot = nullptr;
  const MapState* map = nullptr;
  MotionCommands* motion = nullptr;
  MapCommands* maps = nullptr;
  const sim::World* sim_world = nullptr;  ///< the simulated world, or null for a real robot
  std::string operator_token;             ///< empty: nobody is an operator
  std::filesystem::path web_root;
  /// Browser origins (`scheme://host[:port]`) that may open the WebSocket besides the server's own; "*":
  /// any. Requests without an Origin header (scripts) always may (auth::origin_allowed).
  std::vector<std::string> allowed_origins;
  /// Host header values requests may carry (auth::host_allowed): own_host_names() plus the allowed-hosts
  /// option; "*": any. IP literals are always allowed.
  std::vector<std::string> allowed_hosts;
  /// WebSocket clients at once; one more is refused with 503 at the upgrade.
  std::size_t max_websocket_clients = 256;
  /// TCP connections at once that are not WebSocket clients (HTTP requests, idle keep-alive, connections
  /// still sending their first request); one more is answered 503 and closed.
  std::size_t max_http_connections = 512;
};

}  // namespace strata

#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "server/control/fleet_options.hpp"

namespace strata {

/// How the server meets its clients: where it listens, who may do what, how many at once. One struct from
/// the command line (`strata serve`) to the sessions: an option is a field here, a line in
/// server/app/serve_command.cpp and a key in deploy/strata.example.ini.
struct NetworkOptions {
  std::string bind_address = "0.0.0.0";  ///< 127.0.0.1 keeps the robot's server off the network
  std::uint16_t port = 8080;             ///< 0: a free one, printed at start
  std::filesystem::path web_root;        ///< the web bundle; empty: the one beside the executable
  double pose_rate = 25.0;               ///< Hz; the pose stream, decoupled from the odometry's rate
  int io_threads = 2;                    ///< sessions are strands, so any number of threads is safe
  /// Goals, teleop, save and load need it. Empty: a random one is made and printed at start.
  std::string operator_token;
  std::filesystem::path operator_token_file;  ///< read at start (keeps the token off the command line)
  /// A PEM certificate (chain) and its unencrypted key, both or neither: with them the port serves
  /// https:// and wss:// only.
  std::filesystem::path tls_certificate;
  std::filesystem::path tls_key;
  /// Browser origins besides the server's own that may open the WebSocket ("*": any); scripts send none.
  std::vector<std::string> allowed_origins;
  /// Host names requests may name besides IP literals, localhost and this machine's name ("*": any):
  /// against DNS rebinding. The server adds its own names at start.
  std::vector<std::string> allowed_hosts;
  std::size_t max_clients = 256;           ///< WebSocket clients; one more is refused with 503
  std::size_t max_http_connections = 512;  ///< other TCP connections; one more is answered 503
  /// Connections of every kind from one IP address at once; one more is answered 503.
  std::size_t max_connections_per_address = 64;
  /// Seconds a WebSocket client may stay silent (no message, no answer to the server's ping at half of
  /// it) before it is dropped and counted as not keeping up.
  double client_timeout_s = 20.0;
  FleetOptions fleet;  ///< a fleet master over VDA 5050 (MQTT), beside the browser clients
};

}  // namespace strata

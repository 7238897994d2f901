#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace strata::fleet {

/// Where the MQTT broker is: `mqtt://HOST:PORT` or `mqtts://HOST:PORT` (the port defaults to 1883 and 8883).
struct BrokerAddress {
  std::string host;
  int port = 1883;
  bool tls = false;
};

/// A URL's `HOST[:PORT]`, `[V6]:PORT` part (the "authority" without user@): the host and the port, or
/// `default_port`; none with `error` saying what is wrong. `what` names the server in the error ("broker").
struct HostPort {
  std::string host;
  int port = 0;
};
[[nodiscard]] std::optional<HostPort> parse_host_port(std::string_view authority, int default_port,
                                                      std::string_view what, std::string* error = nullptr);

/// The address in `url`, or none with `error` saying what is wrong with it.
[[nodiscard]] std::optional<BrokerAddress> parse_broker_url(std::string_view url,
                                                            std::string* error = nullptr);

}  // namespace strata::fleet

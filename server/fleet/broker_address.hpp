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

/// The address in `url`, or none with `error` saying what is wrong with it.
[[nodiscard]] std::optional<BrokerAddress> parse_broker_url(std::string_view url,
                                                            std::string* error = nullptr);

}  // namespace strata::fleet

#include "server/fleet/broker_address.hpp"

#include <charconv>

namespace strata::fleet {
namespace {

/// No `T`, and why in `error` (when asked for).
template <typename T>
std::optional<T> refuse(std::string* error, std::string why) {
  if (error != nullptr)
    *error = std::move(why);
  return std::nullopt;
}

}  // namespace

std::optional<BrokerAddress> parse_broker_url(std::string_view url, std::string* error) {
  BrokerAddress address;
  if (url.starts_with("mqtt://")) {
    url.remove_prefix(7);
  } else if (url.starts_with("mqtts://")) {
    url.remove_prefix(8);
    address.tls = true;
    address.port = 8883;
  } else {
    return refuse<BrokerAddress>(error, "the broker must be mqtt://HOST[:PORT] or mqtts://HOST[:PORT]");
  }
  if (!url.empty() && url.back() == '/')
    url.remove_suffix(1);
  const auto host_port = parse_host_port(url, address.port, "broker", error);
  if (!host_port)
    return std::nullopt;
  address.host = host_port->host;
  address.port = host_port->port;
  return address;
}

std::optional<HostPort> parse_host_port(std::string_view url, int default_port, std::string_view what,
                                        std::string* error) {
  const std::string the(std::string("the ") + std::string(what));
  HostPort address{{}, default_port};
  std::string_view host = url;
  // [v6::address]:port, host:port, host
  if (url.starts_with('[')) {
    const auto close = url.find(']');
    if (close == std::string_view::npos)
      return refuse<HostPort>(error, the + "'s IPv6 address has no closing ']'");
    host = url.substr(1, close - 1);
    url.remove_prefix(close + 1);
    if (!url.empty() && url.front() != ':')
      return refuse<HostPort>(error, "after " + the + "'s IPv6 address only :PORT may follow");
  } else {
    const auto colon = url.rfind(':');
    host = url.substr(0, colon);
    url = colon == std::string_view::npos ? std::string_view() : url.substr(colon);
  }
  if (!url.empty()) {
    url.remove_prefix(1);  // ':'
    int port = 0;
    const auto [end, failure] = std::from_chars(url.data(), url.data() + url.size(), port);
    if (failure != std::errc() || end != url.data() + url.size() || port < 1 || port > 65535)
      return refuse<HostPort>(error, the + "'s port must be a number from 1 to 65535");
    address.port = port;
  }
  if (host.empty() || host.find_first_of("/?#@ ") != std::string_view::npos)
    return refuse<HostPort>(error, the + " needs a host name or address (no path, no user@)");
  address.host = std::string(host);
  return address;
}
}  // namespace strata::fleet

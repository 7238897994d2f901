#pragma once

#include "server/net/address_limit.hpp"
#include "server/net/connection_limit.hpp"

namespace strata::net {

/// The places a connection holds under the server's limits, from its accept: one of its address's, until it
/// closes; and one of the HTTP connections', until it closes or becomes a WebSocket client (which then
/// holds a WebSocket place instead, and keeps the address's).
struct ConnectionPlaces {
  AddressLimit::Slot address;
  ConnectionLimit::Slot http;
};

}  // namespace strata::net

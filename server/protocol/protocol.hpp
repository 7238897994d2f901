#pragma once

#include <string_view>

namespace strata::protocol {

/// The WebSocket subprotocol a client asks for (Sec-WebSocket-Protocol). See proto/PROTOCOL.md.
inline constexpr std::string_view kSubprotocol = "strata.v1";
inline constexpr int kVersion = 1;
/// Additive changes within strata.v1 (proto/PROTOCOL.md, "Versioning"). 1: teleop's "seq" and "t", the
/// server clock in hello and pong, the stale_command error.
inline constexpr int kMinorVersion = 1;
/// The largest message a client may send; larger ones close the connection (1009, message too big).
inline constexpr std::size_t kMaxClientMessageBytes = 64 * 1024;

}  // namespace strata::protocol

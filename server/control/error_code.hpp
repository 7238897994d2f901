#pragma once

#include <string_view>

namespace strata {

/// Why a request or a command was refused: the protocol's error codes (proto/PROTOCOL.md, "Error codes"), one
/// enum for the WebSocket, REST and the commands behind both.
enum class ErrorCode {
  kBadJson,
  kBadMessage,
  kUnknownOp,
  kNotFound,
  kMethodNotAllowed,
  kBadRequest,
  kUnavailable,
  kBadParams,     ///< a known op (or REST body) with missing, mistyped or out-of-range fields
  kUnauthorized,  ///< needs the operator token, or the token offered is wrong
  kRateLimited,   ///< the client sends faster than the limit
  kForbidden,     ///< refused whatever the token: a WebSocket from a browser origin that is not allowed
  kCorruptFile,   ///< a saved map failed its checks (truncated, checksum, version); the current map is kept
  kIoError,       ///< the server could not read or write a file
  kStaleCommand,  ///< a teleop that would move the robot arrived too late or out of order: not obeyed
  kInternal,
};
[[nodiscard]] std::string_view to_string(ErrorCode code);

}  // namespace strata

#pragma once

#include <string>
#include <string_view>

namespace strata::auth {

/// Who a request or a connection speaks for. Anyone allowed to connect may watch; moving the robot and
/// saving or loading the map need the operator token (docs/architecture.md 6).
enum class Role { kViewer, kOperator };

/// Equality whose running time depends only on the length of `expected`, not on where the strings differ:
/// comparing a guessed token must not tell the guesser how many leading characters were right.
[[nodiscard]] bool constant_time_equal(std::string_view given, std::string_view expected);

/// A fresh random token (192 bits from std::random_device, base64url without padding: 32 characters, all
/// valid in a WebSocket subprotocol and a cookie).
[[nodiscard]] std::string generate_token();

/// Whether `token` can be carried everywhere a client has to carry it: 16 to 128 characters from the
/// base64url alphabet (A-Z a-z 0-9 - _), which HTTP allows in a subprotocol token, a header and a cookie.
[[nodiscard]] bool is_valid_token(std::string_view token);

}  // namespace strata::auth

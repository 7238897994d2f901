#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "server/auth/operator_token.hpp"
#include "server/protocol/http_types.hpp"

namespace strata::auth {

/// What a request's credentials amount to.
enum class AuthOutcome {
  kViewer,    ///< no token offered (or only a cookie that does not match): may watch
  kOperator,  ///< the operator token, offered in one of the accepted ways
  kBadToken,  ///< a token was offered explicitly and it is wrong: refuse, do not silently downgrade
  /// An Authorization header with another scheme than Bearer (`Token x`, `Basic ...`): refused like a
  /// wrong token, with a reason that says which scheme to use.
  kWrongScheme,
};

/// Why a request with `outcome` kBadToken or kWrongScheme is refused, in words for the client.
[[nodiscard]] std::string_view refusal_reason(AuthOutcome outcome);

/// The subprotocol prefix that carries a token on a WebSocket upgrade: browsers cannot set headers on a
/// WebSocket, so the page offers "strata.v1, strata.token.<token>" (the server echoes only strata.v1).
inline constexpr std::string_view kTokenSubprotocolPrefix = "strata.token.";
/// The cookie a browser page may carry the token in; honoured only when the request's Origin is this server.
inline constexpr std::string_view kTokenCookie = "strata_token";

/// Checks, in order: `Authorization: Bearer <token>`; on a WebSocket upgrade a `strata.token.<token>`
/// subprotocol value; the `strata_token` cookie, but only with an Origin header naming the Host itself, so
/// a page from another site cannot act with the operator's cookie. Tokens never travel in the URL (URLs end
/// up in logs and browser history). An empty `operator_token` makes everyone a viewer.
[[nodiscard]] AuthOutcome authenticate(const protocol::HttpRequest& request, std::string_view operator_token);

/// Whether the request's Origin header names the host in its Host header (scheme ignored).
[[nodiscard]] bool is_same_origin(const protocol::HttpRequest& request);

/// Whether a WebSocket upgrade may proceed as far as its origin goes. Browsers send the page's Origin on
/// every WebSocket, and a page from anywhere may open one to any address it can reach: without this check
/// any web site a user on the robot's network visits could watch the robot (cross-site WebSocket
/// hijacking). Allowed: no Origin header (scripts and tools, which are not browsers), the server's own
/// origin (the web app it serves: is_same_origin), and the origins listed in `allowed_origins` (a kiosk page
/// served elsewhere), or any with "*". "null" (sandboxed frames, file:// pages) only if listed.
[[nodiscard]] bool origin_allowed(const protocol::HttpRequest& request,
                                  const std::vector<std::string>& allowed_origins);

/// Whether `origin` can be an entry of allowed-origins: "*", "null", or `http(s)://host[:port]` without
/// a path (a trailing '/' is tolerated).
[[nodiscard]] bool is_valid_origin_pattern(std::string_view origin);

}  // namespace strata::auth

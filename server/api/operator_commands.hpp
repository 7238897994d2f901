#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string_view>
#include <variant>

#include "server/control/robot_commands.hpp"
#include "server/control/server_services.hpp"
#include "server/protocol/client_messages.hpp"
#include "server/protocol/http_types.hpp"

namespace strata::api {

/// Carries out an operator's command, whichever transport brought it: the WebSocket's messages and the
/// REST bodies validate into the same ClientRequest, and this is the one place that turns it into a call on
/// the robot. It knows nothing of connections: who may ask (the operator token) and whether a teleop is
/// still fresh (TeleopFreshness, per connection) are checked before. A service the server lacks answers
/// kUnavailable; `ping` and `subscribe` are not commands (kInternal).
[[nodiscard]] CommandResult run_operator_command(const ServerServices& services,
                                                 const protocol::ClientRequest& request,
                                                 std::chrono::steady_clock::time_point now);

/// A REST request whose body is the WebSocket message `op` without its "op" (an empty body: {}), with
/// `from_path` added (what the URL names, e.g. a map's name): validated exactly as that message, or the
/// 400 that says why not (bad_json: not JSON, or nested too deep; bad_params: the fields).
[[nodiscard]] std::variant<protocol::ClientRequest, protocol::HttpResponse> command_from_body(
    const protocol::HttpRequest& request, std::string_view op,
    nlohmann::json from_path = nlohmann::json::object());

}  // namespace strata::api

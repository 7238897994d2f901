#include "server/api/operator_commands.hpp"

#include <algorithm>
#include <string>
#include <type_traits>
#include <variant>

#include "drivers/io/json_input.hpp"
#include "server/api/responses.hpp"
#include "server/control/server_clock.hpp"

namespace strata::api {
namespace {

CommandResult unavailable(std::string_view what) {
  return CommandResult::failure(ErrorCode::kUnavailable,
                                std::string(what) + " is not available on this server");
}

}  // namespace

CommandResult run_operator_command(const ServerServices& services, const protocol::ClientRequest& request,
                                   std::chrono::steady_clock::time_point now) {
  MotionCommands* motion = services.motion;
  MapCommands* maps = services.maps;
  return std::visit(
      [&](const auto& r) -> CommandResult {
        using T = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<T, protocol::SetGoalRequest>) {
          return motion != nullptr ? motion->set_goal(r.goal) : unavailable("navigation");
        } else if constexpr (std::is_same_v<T, protocol::CancelGoalRequest>) {
          return motion != nullptr ? motion->cancel_goal() : unavailable("navigation");
        } else if constexpr (std::is_same_v<T, protocol::TeleopRequest>) {
          if (motion == nullptr)
            return unavailable("teleoperation");
          // The lease runs from when it was sent; a stamp ahead of the clock counts as sent now.
          const auto sent = r.stamp ? std::min(from_server_clock_ms(r.stamp->sent_ms), now) : now;
          return motion->teleop(r.v, r.w, sent);
        } else if constexpr (std::is_same_v<T, protocol::SaveMapRequest>) {
          return maps != nullptr ? maps->save_map(r.name) : unavailable("map saving");
        } else if constexpr (std::is_same_v<T, protocol::LoadMapRequest>) {
          return maps != nullptr ? maps->load_map(r.name, r.mode) : unavailable("map loading");
        } else if constexpr (std::is_same_v<T, protocol::SetPoseRequest>) {
          return services.localization != nullptr ? services.localization->set_pose_estimate(r.estimate)
                                                  : unavailable("pose estimates");
        } else {
          return CommandResult::failure(ErrorCode::kInternal, "not an operator command");
        }
      },
      request);
}

std::variant<protocol::ClientRequest, protocol::HttpResponse> command_from_body(
    const protocol::HttpRequest& request, std::string_view op, nlohmann::json from_path) {
  namespace http = protocol::http;
  nlohmann::json message = nlohmann::json::object();
  if (!request.body().empty()) {
    io::JsonInput body = io::parse_json(request.body());
    if (!body.ok())
      return error_response(request, http::status::bad_request, ErrorCode::kBadJson,
                            "the body is " + body.error);
    if (!body.value.is_object()) {
      return error_response(request, http::status::bad_request, ErrorCode::kBadJson,
                            "the body must be a JSON object");
    }
    message = std::move(body.value);
  }
  for (auto& [key, value] : from_path.items()) {
    if (message.contains(key)) {
      return error_response(request, http::status::bad_request, ErrorCode::kBadParams,
                            "\"" + key + "\" is given by the URL, not the body");
    }
    message[key] = std::move(value);
  }
  message["op"] = op;
  auto parsed = protocol::validate_client_message(message);
  if (!parsed.request)
    return error_response(request, http::status::bad_request, parsed.error, parsed.error_message);
  return std::move(*parsed.request);
}

}  // namespace strata::api

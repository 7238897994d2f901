// REST: the goal (GET, POST to set, DELETE to cancel), the planned path, the operator's pose estimate, and
// the IMU calibration kept between runs (GET, DELETE to forget it).
#include <chrono>
#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/http_router.hpp"
#include "server/api/operator_commands.hpp"
#include "server/api/responses.hpp"
#include "server/protocol/client_messages.hpp"
#include "server/protocol/messages.hpp"

namespace strata::api {

namespace http = protocol::http;
using protocol::ErrorCode;

protocol::HttpResponse HttpRouter::goal(const protocol::HttpRequest& request) const {
  MotionCommands* motion = services_.motion;
  const bool write = request.method() == http::verb::post || request.method() == http::verb::delete_;
  if (!is_read(request) && !write)
    return method_not_allowed(request, "GET, HEAD, POST, DELETE");
  if (write) {
    if (auto refusal = require_operator(request))
      return std::move(*refusal);
  }
  const auto unavailable = [&] {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "navigation is not available on this server");
  };
  if (request.method() == http::verb::post) {
    // The body is the WebSocket set_goal message without "op": one validation, one command for both.
    auto command = command_from_body(request, "set_goal");
    if (auto* refusal = std::get_if<protocol::HttpResponse>(&command))
      return std::move(*refusal);
    if (motion == nullptr)
      return unavailable();
    const CommandResult result = run_operator_command(services_, std::get<protocol::ClientRequest>(command),
                                                      std::chrono::steady_clock::now());
    if (!result.ok)
      return command_error(request, result.code, result.message);
    return json_response(request, http::status::accepted,
                         protocol::goal_fields(motion->goal_status()).dump());
  }
  if (motion == nullptr)
    return unavailable();
  if (request.method() == http::verb::delete_) {
    const CommandResult result = motion->cancel_goal();
    if (!result.ok)
      return command_error(request, result.code, result.message);
  }
  return json_response(request, http::status::ok, protocol::goal_fields(motion->goal_status()).dump());
}

protocol::HttpResponse HttpRouter::path(const protocol::HttpRequest& request) const {
  if (services_.motion == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "navigation is not available on this server");
  }
  const auto planned = services_.motion->path();
  return json_response(request, http::status::ok, protocol::path_fields(planned.get()).dump());
}

protocol::HttpResponse HttpRouter::pose_estimate(const protocol::HttpRequest& request) const {
  if (request.method() != http::verb::post)
    return method_not_allowed(request, "POST");
  if (auto refusal = require_operator(request))
    return std::move(*refusal);
  // The body is the WebSocket set_pose message without "op": one validation, one command for both.
  auto command = command_from_body(request, "set_pose");
  if (auto* refusal = std::get_if<protocol::HttpResponse>(&command))
    return std::move(*refusal);
  const CommandResult result = run_operator_command(services_, std::get<protocol::ClientRequest>(command),
                                                    std::chrono::steady_clock::now());
  if (!result.ok)
    return command_error(request, result.code, result.message);
  return json_response(request, http::status::accepted, nlohmann::json{{"message", result.message}}.dump());
}

protocol::HttpResponse HttpRouter::imu_calibration(const protocol::HttpRequest& request) const {
  const bool clear = request.method() == http::verb::delete_;
  if (!is_read(request) && !clear)
    return method_not_allowed(request, "GET, HEAD, DELETE");
  if (clear) {
    if (auto refusal = require_operator(request))
      return std::move(*refusal);
  }
  CalibrationCommands* calibration = services_.calibration;
  if (calibration == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "no IMU calibration is kept on this server");
  }
  nlohmann::json answer;
  if (clear) {
    const CommandResult result = calibration->clear_imu_calibration();
    if (!result.ok)
      return command_error(request, result.code, result.message);
    answer["message"] = result.message;
  }
  answer.update(protocol::imu_calibration_fields(calibration->imu_calibration()));
  return json_response(request, http::status::ok,
                       answer.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

}  // namespace strata::api

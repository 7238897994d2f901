// REST: the goal (GET, POST to set, DELETE to cancel), the planned path, the operator's pose estimate, and
// the IMU calibration kept between runs (GET, DELETE to forget it).
#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/http_router.hpp"
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
    // The body is the WebSocket set_goal message without "op": one validation for both.
    nlohmann::json body = nlohmann::json::parse(request.body(), nullptr, /*allow_exceptions=*/false);
    if (body.is_discarded() || !body.is_object()) {
      return error_response(request, http::status::bad_request, ErrorCode::kBadJson,
                            "the body must be a JSON object {\"x\": ..., \"y\": ..., \"z\": ...}");
    }
    body["op"] = "set_goal";
    const auto parsed = protocol::parse_client_message(body.dump());
    if (!parsed.request) {
      return error_response(request, http::status::bad_request, parsed.error, parsed.error_message);
    }
    if (motion == nullptr)
      return unavailable();
    const CommandResult result = motion->set_goal(std::get<protocol::SetGoalRequest>(*parsed.request).goal);
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
  // The body is the WebSocket set_pose message without "op": one validation for both.
  nlohmann::json body = nlohmann::json::parse(request.body(), nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded() || !body.is_object()) {
    return error_response(request, http::status::bad_request, ErrorCode::kBadJson,
                          "the body must be a JSON object {\"x\": ..., \"y\": ..., \"yaw\": ...}");
  }
  body["op"] = "set_pose";
  const auto parsed = protocol::parse_client_message(body.dump());
  if (!parsed.request)
    return error_response(request, http::status::bad_request, parsed.error, parsed.error_message);
  if (services_.localization == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "localization is not available on this server");
  }
  const CommandResult result =
      services_.localization->set_pose_estimate(std::get<protocol::SetPoseRequest>(*parsed.request).estimate);
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

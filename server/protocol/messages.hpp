#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world.hpp"
#include "server/state/robot_state.hpp"

namespace strata::protocol {

/// Error codes carried by `error` messages and REST error bodies (proto/PROTOCOL.md, "Errors").
enum class ErrorCode {
  kBadJson,
  kBadMessage,
  kUnknownOp,
  kNotFound,
  kMethodNotAllowed,
  kBadRequest,
  kUnavailable,
};
[[nodiscard]] std::string_view to_string(ErrorCode code);

/// The pose fields shared by the `pose` WebSocket message and GET /api/v1/pose.
[[nodiscard]] nlohmann::json pose_fields(const RobotSnapshot& robot);
/// {"op":"pose", ...}: the live pose stream.
[[nodiscard]] std::string pose_message(const RobotSnapshot& robot);
/// The body of GET /api/v1/status: registration quality and counts.
[[nodiscard]] nlohmann::json status_fields(const RegistrationStatus& registration, std::size_t clients);
/// {"op":"status", ...}: the status stream (1 Hz).
[[nodiscard]] std::string status_message(const RegistrationStatus& registration, std::size_t clients);
/// The simulated world's geometry (boxes, ramps, cylinders, spheres, terrain), for drawing it faintly: the
/// body of GET /api/v1/sim/world.
[[nodiscard]] nlohmann::json sim_world(const sim::World& world);
/// {"op":"sim_world", ...}: the same, sent to late joiners when the robot is simulated.
[[nodiscard]] std::string sim_world_message(const sim::World& world);
/// {"op":"hello", ...}: the first message on every connection.
[[nodiscard]] std::string hello_message();
/// {"op":"error","code":...,"message":...}
[[nodiscard]] std::string error_message(ErrorCode code, std::string_view message);
/// {"op":"pong", "id": ...}
[[nodiscard]] std::string pong_message(const nlohmann::json& id);
/// The body of GET /api/v1/info.
[[nodiscard]] nlohmann::json info();
/// The REST error body {"error":{"code":...,"message":...}}.
[[nodiscard]] std::string rest_error(ErrorCode code, std::string_view message);

}  // namespace strata::protocol

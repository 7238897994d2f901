#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "drivers/robot_sample.hpp"
#include "drivers/sim/world/world.hpp"
#include "server/control/error_code.hpp"
#include "server/state/goal_state.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata::protocol {

/// Error codes carried by `error` messages and REST error bodies (proto/PROTOCOL.md, "Errors").
using strata::ErrorCode;  // the codes live below the protocol: commands answer with them too

/// The pose fields shared by the `pose` WebSocket message and GET /api/v1/pose.
[[nodiscard]] nlohmann::json pose_fields(const RobotSnapshot& robot);
/// {"op":"pose", ...}: the live pose stream.
[[nodiscard]] std::string pose_message(const RobotSnapshot& robot);
/// What the status stream reports besides registration.
struct StatusExtras {
  std::size_t clients = 0;
  double scan_rate = 0.0;                  ///< scans registered per second, recent average
  std::shared_ptr<const MapSnapshot> map;  ///< null before the first map
  DriverStatus driver;                     ///< where the scans come from
  SensorStatus sensor;                     ///< whether its scans arrive when due
};
/// The body of GET /api/v1/status: registration quality and counts, scan rate, map size, clients.
[[nodiscard]] nlohmann::json status_fields(const RegistrationStatus& registration,
                                           const StatusExtras& extras);
/// {"op":"status", ...}: the status stream (1 Hz).
[[nodiscard]] std::string status_message(const RegistrationStatus& registration, const StatusExtras& extras);
/// The body of GET /api/v1/goal and the `goal` message's fields.
/// The IMU calibration kept between runs: the status's pose_graph.imu_calibration and
/// GET /api/v1/imu-calibration.
[[nodiscard]] nlohmann::json imu_calibration_fields(const ImuCalibrationStatus& calibration);
[[nodiscard]] nlohmann::json goal_fields(const GoalStatus& goal);
[[nodiscard]] std::string goal_message(const GoalStatus& goal);
/// The body of GET /api/v1/path and the `path` message's fields; `path` may be null (no path).
[[nodiscard]] nlohmann::json path_fields(const PlannedPath* path);
[[nodiscard]] std::string path_message(const PlannedPath* path);
/// {"op":"ack","request":op,"id":id}: a command was accepted.
/// `message`: what the command did, when there is more to say than "accepted" (empty: none).
[[nodiscard]] std::string ack_message(std::string_view request_op, const nlohmann::json& id,
                                      std::string_view message = {});
/// The simulated world's geometry (boxes, ramps, cylinders, spheres, terrain), for drawing it faintly: the
/// body of GET /api/v1/sim/world.
[[nodiscard]] nlohmann::json sim_world(const sim::World& world);
/// {"op":"sim_world", ...}: the same, sent to late joiners when the robot is simulated.
[[nodiscard]] std::string sim_world_message(const sim::World& world);
/// {"op":"hello", ...}: the first message on every connection; `role` is "operator" or "viewer".
/// `clock_ms`: the server clock (control/server_clock.hpp) that clients stamp teleop commands in.
[[nodiscard]] std::string hello_message(std::string_view role, double clock_ms);
/// {"op":"error","code":...,"message":...[,"request":op][,"id":id]}
[[nodiscard]] std::string error_message(ErrorCode code, std::string_view message,
                                        std::string_view request_op = {}, const nlohmann::json& id = nullptr);
/// An error code given as text by a command implementation (CommandResult::code).
[[nodiscard]] std::string error_message(std::string_view code, std::string_view message,
                                        std::string_view request_op, const nlohmann::json& id);
/// {"op":"pong", "id": ...}
[[nodiscard]] std::string pong_message(const nlohmann::json& id, double clock_ms);
/// The body of GET /api/v1/info.
[[nodiscard]] nlohmann::json info();
/// The REST error body {"error":{"code":...,"message":...}}.
[[nodiscard]] std::string rest_error(ErrorCode code, std::string_view message);

}  // namespace strata::protocol

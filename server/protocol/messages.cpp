#include "server/protocol/messages.hpp"

#include <chrono>

#include "server/protocol/build_info.hpp"
#include "server/protocol/protocol.hpp"

namespace strata::protocol {
namespace {

nlohmann::json pose_json(const Pose3& pose) {
  return {{"x", pose.position.x()}, {"y", pose.position.y()}, {"z", pose.position.z()},
          {"roll", pose.roll},      {"pitch", pose.pitch},    {"yaw", pose.yaw}};
}

}  // namespace

nlohmann::json pose_fields(const RobotSnapshot& robot) {
  const RobotSample& sample = robot.sample;
  nlohmann::json fields = pose_json(robot.estimate);
  fields["stamp"] = sample.stamp;
  fields["frame"] = "map";
  fields["source"] = robot.localized ? "registration" : "odometry";
  fields["odometry"] = pose_json(sample.odometry);
  if (sample.truth)  // none from a lidar: nothing knows where it truly is
    fields["truth"] = pose_json(*sample.truth);
  // Standing only where the base says so: a replay or a lidar alone does not know its velocity.
  const bool standing = sample.velocity_known && sample.velocity.v == 0.0 && sample.velocity.w == 0.0;
  fields["mode"] = !sample.blocked_by.empty() ? "blocked"
                   : sample.scanning          ? "scanning"
                   : standing                 ? "standing"
                                              : "driving";
  return fields;
}

std::string pose_message(const RobotSnapshot& robot) {
  nlohmann::json message = pose_fields(robot);
  message["op"] = "pose";
  // When it left the server, wall clock: a client on the same clock (loopback, NTP) measures latency.
  message["server_time"] =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  return message.dump();
}

nlohmann::json imu_calibration_fields(const ImuCalibrationStatus& calibration) {
  nlohmann::json fields{{"kept", to_string(calibration.kept)},
                        {"imu", calibration.imu.empty() ? nlohmann::json() : nlohmann::json(calibration.imu)},
                        {"roll_deg", nullptr},
                        {"pitch_deg", nullptr},
                        {"loops", calibration.loops}};
  if (calibration.mounting_deg) {
    fields["roll_deg"] = calibration.mounting_deg->x();
    fields["pitch_deg"] = calibration.mounting_deg->y();
  }
  return fields;
}

nlohmann::json status_fields(const RegistrationStatus& registration, const StatusExtras& extras) {
  nlohmann::json reg{{"scans", registration.scans},       {"accepted", registration.accepted},
                     {"rejected", registration.rejected}, {"partial", registration.partial},
                     {"dropped", registration.dropped},   {"kept_odometry", registration.kept_odometry},
                     {"full", registration.full}};
  if (registration.last) {
    const auto& last = *registration.last;
    reg["last"] = {{"stamp", last.stamp},   {"verdict", last.verdict},       {"correction", last.correction},
                   {"reason", last.reason}, {"message", last.message},       {"rmse", last.rmse},
                   {"pairs", last.pairs},   {"iterations", last.iterations}, {"seconds", last.seconds}};
  }
  const PoseGraphStatus& graph = registration.graph;
  nlohmann::json pose_graph{{"keyframes", graph.keyframes},
                            {"loops", graph.loops},
                            {"loops_dropped", graph.loops_dropped},
                            {"optimizations", graph.optimizations},
                            {"last_loop_stamp", nullptr},
                            {"last_correction_m", graph.last_correction},
                            {"heading_drift_deg_per_h", graph.heading_drift_deg_per_h()},
                            {"gravity_mounting_roll_deg", graph.gravity_mounting_deg().x()},
                            {"gravity_mounting_pitch_deg", graph.gravity_mounting_deg().y()},
                            {"imu_calibration", imu_calibration_fields(registration.imu_calibration)}};
  if (graph.last_loop_stamp >= 0.0)
    pose_graph["last_loop_stamp"] = graph.last_loop_stamp;
  nlohmann::json map{{"version", 0}, {"tiles", 0},    {"cells", 0},       {"patches", 0},
                     {"bytes", 0},   {"rebuilds", 0}, {"mode", "mapping"}};
  if (extras.map) {
    map = {{"version", extras.map->version},
           {"tiles", extras.map->tiles.size()},
           {"cells", extras.map->cells},
           {"patches", extras.map->patches},
           {"bytes", extras.map->memory_bytes},
           {"rebuilds", extras.map->rebuilds},
           {"mode", extras.map->localizing ? "localize" : "mapping"}};
  }
  nlohmann::json sensor{{"state", extras.sensor.stalled ? "stalled" : "ok"},
                        {"overdue_seconds", extras.sensor.overdue},
                        {"timeout_seconds", extras.sensor.timeout},
                        {"scans", extras.sensor.scans}};
  if (extras.sensor.seconds_since_last_scan)
    sensor["seconds_since_last_scan"] = *extras.sensor.seconds_since_last_scan;
  const LocalizationHealth& health = registration.localization;
  nlohmann::json relocalization = nullptr;
  if (registration.relocalization) {
    relocalization = {{"stamp", registration.relocalization->stamp},
                      {"found", registration.relocalization->found},
                      {"message", registration.relocalization->message}};
  }
  return {{"localization", {{"state", to_string(health.state)}, {"reason", health.reason}}},
          {"relocalization", std::move(relocalization)},
          {"registration", std::move(reg)},
          {"pose_graph", std::move(pose_graph)},
          {"clients", extras.clients},
          {"scan_rate", extras.scan_rate},
          {"map", std::move(map)},
          {"driver", {{"kind", extras.driver.kind}, {"finished", extras.driver.finished}}},
          {"sensor", std::move(sensor)}};
}

std::string status_message(const RegistrationStatus& registration, const StatusExtras& extras) {
  nlohmann::json message = status_fields(registration, extras);
  message["op"] = "status";
  return message.dump();
}

nlohmann::json goal_fields(const GoalStatus& goal) {
  if (goal.id == 0)
    return {{"id", 0}, {"phase", "none"}};
  nlohmann::json fields{{"id", goal.id},
                        {"x", goal.target.x},
                        {"y", goal.target.y},
                        {"phase", to_string(goal.phase)},
                        {"stamp", goal.stamp}};
  if (goal.target.z)
    fields["z"] = *goal.target.z;
  if (!goal.reason.empty())
    fields["reason"] = goal.reason;
  if (!goal.message.empty())
    fields["message"] = goal.message;
  if (goal.nearest_reachable)
    fields["nearest"] = {{"x", goal.nearest_reachable->x()},
                         {"y", goal.nearest_reachable->y()},
                         {"z", goal.nearest_reachable->z()}};
  return fields;
}

std::string goal_message(const GoalStatus& goal) {
  nlohmann::json message = goal_fields(goal);
  message["op"] = "goal";
  return message.dump();
}

nlohmann::json path_fields(const PlannedPath* path) {
  nlohmann::json points = nlohmann::json::array();
  if (path == nullptr)
    return {{"goal_id", 0}, {"version", 0}, {"length", 0.0}, {"points", std::move(points)}};
  for (const auto& point : path->points)
    points.push_back({point.x(), point.y(), point.z()});
  return {{"goal_id", path->goal_id},
          {"version", path->version},
          {"length", path->length},
          {"points", std::move(points)}};
}

std::string path_message(const PlannedPath* path) {
  nlohmann::json message = path_fields(path);
  message["op"] = "path";
  return message.dump();
}

std::string ack_message(std::string_view request_op, const nlohmann::json& id, std::string_view note) {
  nlohmann::json message{{"op", "ack"}, {"request", request_op}};
  if (!id.is_null())
    message["id"] = id;
  if (!note.empty())
    message["message"] = note;
  return message.dump();
}

nlohmann::json sim_world(const sim::World& world) {
  const sim::WorldDescription& d = world.description();
  auto vec = [](const auto& v) {
    nlohmann::json array = nlohmann::json::array();
    for (Eigen::Index k = 0; k < v.size(); ++k)
      array.push_back(v[k]);
    return array;
  };
  nlohmann::json boxes = nlohmann::json::array();
  for (const auto& box : d.boxes) {
    boxes.push_back(
        {{"name", box.name}, {"center", vec(box.center)}, {"size", vec(box.size)}, {"yaw", box.yaw}});
  }
  nlohmann::json ramps = nlohmann::json::array();
  for (const auto& ramp : d.ramps) {
    ramps.push_back({{"name", ramp.name},
                     {"center", vec(ramp.center)},
                     {"length", ramp.length},
                     {"width", ramp.width},
                     {"yaw", ramp.yaw},
                     {"base_z", ramp.base_z},
                     {"height_start", ramp.height_start},
                     {"height_end", ramp.height_end}});
  }
  nlohmann::json cylinders = nlohmann::json::array();
  for (const auto& c : d.cylinders) {
    cylinders.push_back(
        {{"center", vec(c.center)}, {"radius", c.radius}, {"z_min", c.z_min}, {"z_max", c.z_max}});
  }
  nlohmann::json spheres = nlohmann::json::array();
  for (const auto& s : d.spheres)
    spheres.push_back({{"center", vec(s.center)}, {"radius", s.radius}});
  nlohmann::json result{{"name", d.name},
                        {"summary", d.summary},
                        {"bounds", {{"min", vec(world.bounds().min)}, {"max", vec(world.bounds().max)}}},
                        {"boxes", std::move(boxes)},
                        {"ramps", std::move(ramps)},
                        {"cylinders", std::move(cylinders)},
                        {"spheres", std::move(spheres)}};
  if (d.terrain) {
    result["terrain"] = {{"origin", vec(d.terrain->origin())},
                         {"cell", d.terrain->cell()},
                         {"nx", d.terrain->nx()},
                         {"ny", d.terrain->ny()},
                         {"heights", d.terrain->heights()}};
  }
  return result;
}

std::string sim_world_message(const sim::World& world) {
  nlohmann::json message = sim_world(world);
  message["op"] = "sim_world";
  return message.dump();
}

std::string hello_message(std::string_view role, double clock_ms) {
  return nlohmann::json{{"op", "hello"},
                        {"server", "strata"},
                        {"version", build_info::version()},
                        {"protocol", kSubprotocol},
                        {"protocol_version", kVersion},
                        {"protocol_minor", kMinorVersion},
                        {"role", role},
                        {"clock_ms", clock_ms}}
      .dump();
}

std::string error_message(ErrorCode code, std::string_view message, std::string_view request_op,
                          const nlohmann::json& id) {
  return error_message(to_string(code), message, request_op, id);
}

std::string error_message(std::string_view code, std::string_view message, std::string_view request_op,
                          const nlohmann::json& id) {
  nlohmann::json error{{"op", "error"}, {"code", code}, {"message", message}};
  if (!request_op.empty())
    error["request"] = request_op;
  if (!id.is_null())
    error["id"] = id;
  return error.dump();
}

std::string pong_message(const nlohmann::json& id, double clock_ms) {
  nlohmann::json message{{"op", "pong"}, {"clock_ms", clock_ms}};
  if (!id.is_null())
    message["id"] = id;
  return message.dump();
}

nlohmann::json info() {
  return {{"name", "strata"},         {"version", build_info::version()},
          {"protocol", kSubprotocol}, {"protocol_version", kVersion},
          {"source", "simulator"},    {"libraries", build_info::libraries()}};
}

std::string rest_error(ErrorCode code, std::string_view message) {
  // The message may quote what a client sent (a request path) or a file name: not necessarily UTF-8, which
  // JSON must be. Invalid bytes become U+FFFD instead of dump() throwing (found by fuzzing).
  return nlohmann::json{{"error", {{"code", to_string(code)}, {"message", message}}}}.dump(
      -1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace strata::protocol

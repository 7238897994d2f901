#include "server/protocol/messages.hpp"

#include "server/app/build_info.hpp"
#include "server/protocol/protocol.hpp"

namespace strata::protocol {
namespace {

nlohmann::json pose_json(const Pose3& pose) {
  return {{"x", pose.position.x()}, {"y", pose.position.y()}, {"z", pose.position.z()},
          {"roll", pose.roll},      {"pitch", pose.pitch},    {"yaw", pose.yaw}};
}

}  // namespace

std::string_view to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::kBadJson:
      return "bad_json";
    case ErrorCode::kBadMessage:
      return "bad_message";
    case ErrorCode::kUnknownOp:
      return "unknown_op";
    case ErrorCode::kNotFound:
      return "not_found";
    case ErrorCode::kMethodNotAllowed:
      return "method_not_allowed";
    case ErrorCode::kBadRequest:
      return "bad_request";
    case ErrorCode::kUnavailable:
      return "unavailable";
  }
  return "internal";
}

nlohmann::json pose_fields(const RobotSnapshot& robot) {
  const sim::RobotSample& sample = robot.sample;
  nlohmann::json fields = pose_json(robot.estimate);
  fields["stamp"] = sample.stamp;
  fields["frame"] = "map";
  fields["source"] = robot.localized ? "registration" : "odometry";
  fields["odometry"] = pose_json(sample.odometry);
  fields["truth"] = pose_json(sample.truth);
  fields["mode"] = !sample.blocked_by.empty() ? "blocked" : sample.scanning ? "scanning" : "driving";
  return fields;
}

std::string pose_message(const RobotSnapshot& robot) {
  nlohmann::json message = pose_fields(robot);
  message["op"] = "pose";
  return message.dump();
}

nlohmann::json status_fields(const RegistrationStatus& registration, std::size_t clients) {
  nlohmann::json reg{{"scans", registration.scans},
                     {"accepted", registration.accepted},
                     {"rejected", registration.rejected},
                     {"partial", registration.partial},
                     {"dropped", registration.dropped}};
  if (registration.last) {
    const auto& last = *registration.last;
    reg["last"] = {{"stamp", last.stamp},   {"verdict", last.verdict},       {"correction", last.correction},
                   {"reason", last.reason}, {"message", last.message},       {"rmse", last.rmse},
                   {"pairs", last.pairs},   {"iterations", last.iterations}, {"seconds", last.seconds}};
  }
  return {{"registration", std::move(reg)}, {"clients", clients}};
}

std::string status_message(const RegistrationStatus& registration, std::size_t clients) {
  nlohmann::json message = status_fields(registration, clients);
  message["op"] = "status";
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

std::string hello_message() {
  return nlohmann::json{{"op", "hello"},
                        {"server", "strata"},
                        {"version", build_info::version()},
                        {"protocol", kSubprotocol},
                        {"protocol_version", kVersion}}
      .dump();
}

std::string error_message(ErrorCode code, std::string_view message) {
  return nlohmann::json{{"op", "error"}, {"code", to_string(code)}, {"message", message}}.dump();
}

std::string pong_message(const nlohmann::json& id) {
  nlohmann::json message{{"op", "pong"}};
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
  return nlohmann::json{{"error", {{"code", to_string(code)}, {"message", message}}}}.dump();
}

}  // namespace strata::protocol

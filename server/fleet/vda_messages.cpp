#include "server/fleet/vda_messages.hpp"

#include <cstdio>
#include <ctime>

#include "server/fleet/instant_actions.hpp"
#include "server/fleet/order.hpp"

namespace strata::fleet {

using nlohmann::json;

std::string VehicleId::topic(std::string_view name) const {
  return interface_name + "/v2/" + manufacturer + "/" + serial_number + "/" + std::string(name);
}

std::string iso_timestamp(std::chrono::system_clock::time_point time) {
  const auto since_epoch = time.time_since_epoch();
  const auto seconds = std::chrono::floor<std::chrono::seconds>(since_epoch);
  const auto millis = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds).count();
  const std::time_t whole = static_cast<std::time_t>(seconds.count());
  std::tm utc{};
  gmtime_r(&whole, &utc);
  char text[40];
  const std::size_t length = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  char fraction[8];
  std::snprintf(fraction, sizeof fraction, ".%03dZ", static_cast<int>(millis));
  return std::string(text, length) + fraction;
}

json HeaderStamp::stamp(json body, std::chrono::system_clock::time_point now) {
  body["headerId"] = next_++;
  body["timestamp"] = iso_timestamp(now);
  body["version"] = kVdaVersion;
  body["manufacturer"] = id_.manufacturer;
  body["serialNumber"] = id_.serial_number;
  return body;
}

namespace {

json position_json(const AgvPosition& position) {
  json out{{"x", position.x},
           {"y", position.y},
           {"theta", position.theta},
           {"mapId", position.map_id},
           {"positionInitialized", position.initialized}};
  if (position.localization_score)
    out["localizationScore"] = *position.localization_score;
  if (position.deviation_range)
    out["deviationRange"] = *position.deviation_range;
  return out;
}

json velocity_json(const Velocity& velocity) {
  return {{"vx", velocity.vx}, {"vy", 0.0}, {"omega", velocity.omega}};
}

json error_json(const VehicleError& error) {
  json references = json::array();
  for (const auto& [key, value] : error.references)
    references.push_back({{"referenceKey", key}, {"referenceValue", value}});
  return {{"errorType", error.type},
          {"errorLevel", error.level},
          {"errorDescription", error.description},
          {"errorReferences", std::move(references)}};
}

json action_json(const ActionState& action) {
  json out{
      {"actionId", action.action_id}, {"actionType", action.action_type}, {"actionStatus", action.status}};
  if (!action.result.empty())
    out["resultDescription"] = action.result;
  return out;
}

json node_state_json(const NodeState& node) {
  json position{{"x", node.x}, {"y", node.y}, {"mapId", node.map_id}};
  if (node.theta)
    position["theta"] = *node.theta;
  return {{"nodeId", node.node_id},
          {"sequenceId", node.sequence_id},
          {"released", node.released},
          {"nodePosition", std::move(position)}};
}

}  // namespace

json state_body(const VehicleReport& report) {
  json maps = json::array();
  for (const auto& map : report.maps) {
    maps.push_back({{"mapId", map.map_id},
                    {"mapVersion", map.map_version},
                    {"mapStatus", map.enabled ? "ENABLED" : "DISABLED"}});
  }
  json errors = json::array();
  for (const auto& error : report.errors)
    errors.push_back(error_json(error));
  json actions = json::array();
  for (const auto& action : report.actions)
    actions.push_back(action_json(action));
  json nodes = json::array();
  for (const auto& node : report.node_states)
    nodes.push_back(node_state_json(node));
  json edges = json::array();
  for (const auto& edge : report.edge_states)
    edges.push_back(
        {{"edgeId", edge.edge_id}, {"sequenceId", edge.sequence_id}, {"released", edge.released}});
  json body{{"orderId", report.order_id},
            {"orderUpdateId", report.order_update_id},
            {"lastNodeId", report.last_node_id},
            {"lastNodeSequenceId", report.last_node_sequence_id},
            {"nodeStates", std::move(nodes)},
            {"edgeStates", std::move(edges)},
            {"maps", std::move(maps)},
            {"driving", report.driving},
            {"paused", report.paused},
            {"newBaseRequest", false},
            {"operatingMode", "AUTOMATIC"},
            {"actionStates", std::move(actions)},
            // Strata knows no battery: a charge of 0 that says so in no uncertain terms (docs/fleet.md).
            {"batteryState", {{"batteryCharge", 0.0}, {"charging", false}}},
            {"errors", std::move(errors)},
            {"information", json::array()},
            {"loads", json::array()},
            // Strata has no e-stop input: its Stop cancels the goal, which needs no acknowledgement.
            {"safetyState", {{"eStop", "NONE"}, {"fieldViolation", false}}}};
  if (report.position)
    body["agvPosition"] = position_json(*report.position);
  if (report.velocity)
    body["velocity"] = velocity_json(*report.velocity);
  return body;
}

json visualization_body(const VehicleReport& report) {
  json body = json::object();
  if (report.position)
    body["agvPosition"] = position_json(*report.position);
  if (report.velocity)
    body["velocity"] = velocity_json(*report.velocity);
  return body;
}

json connection_body(std::string_view connection_state) {
  return {{"connectionState", connection_state}};
}

const std::vector<std::string>& supported_instant_actions() {
  static const std::vector<std::string> kActions{"factsheetRequest", "stateRequest", "initPosition",
                                                 "startPause",       "stopPause",    "cancelOrder",
                                                 "downloadMap",      "enableMap",    "deleteMap"};
  return kActions;
}

json factsheet_body(const VehicleFacts& facts) {
  json actions = json::array();
  for (const auto& type : supported_instant_actions()) {
    json action{{"actionType", type}, {"actionScopes", {"INSTANT"}}};
    if (type == "initPosition") {
      action["actionParameters"] = {
          {{"key", "x"}, {"valueDataType", "NUMBER"}},
          {{"key", "y"}, {"valueDataType", "NUMBER"}},
          {{"key", "theta"}, {"valueDataType", "NUMBER"}},
          {{"key", "mapId"}, {"valueDataType", "STRING"}},
          {{"key", "lastNodeId"}, {"valueDataType", "STRING"}, {"isOptional", true}}};
    }
    if (type == "downloadMap" || type == "enableMap" || type == "deleteMap") {
      action["actionParameters"] = {{{"key", "mapId"}, {"valueDataType", "STRING"}},
                                    {{"key", "mapVersion"}, {"valueDataType", "STRING"}}};
      if (type == "downloadMap") {
        action["actionParameters"].push_back({{"key", "mapDownloadLink"}, {"valueDataType", "STRING"}});
        action["actionParameters"].push_back({{"key", "mapHash"},
                                              {"valueDataType", "STRING"},
                                              {"description", "SHA-256 of the file, 64 hex digits"},
                                              {"isOptional", true}});
      }
    }
    actions.push_back(std::move(action));
  }
  const double diameter = 2.0 * facts.radius;
  return {
      {"typeSpecification",
       {{"seriesName", "Strata"},
        {"seriesDescription", "a robot localizing and mapping with Strata's 3-D multi-level surface map"},
        {"agvKinematic", "DIFF"},
        {"agvClass", "CARRIER"},
        {"maxLoadMass", 0.0},
        {"localizationTypes", {"NATURAL"}},
        {"navigationTypes", {"AUTONOMOUS"}}}},
      {"physicalParameters",
       {{"speedMin", 0.0},
        {"speedMax", facts.max_speed},
        // Nominal: the base's limits are its driver's; Strata's pure pursuit changes speed gently.
        {"accelerationMax", 0.5},
        {"decelerationMax", 0.5},
        {"heightMax", facts.height},
        {"width", diameter},
        {"length", diameter}}},
      {"protocolLimits",
       {{"maxStringLens", {{"idLen", 256}}},
        // What the order and instant actions' checks take (order.hpp, instant_actions.hpp): no node or
        // edge actions.
        {"maxArrayLens",
         {{"order.nodes", kMaxOrderNodes},
          {"order.edges", kMaxOrderNodes - 1},
          {"node.actions", 0},
          {"edge.actions", 0},
          {"instantActions", kMaxInstantActions}}},
        {"timing", {{"minOrderInterval", 1.0}, {"minStateInterval", 0.1}, {"defaultStateInterval", 30.0}}}}},
      {"protocolFeatures", {{"optionalParameters", json::array()}, {"agvActions", std::move(actions)}}},
      {"agvGeometry", json::object()},
      {"loadSpecification", json::object()}};
}

}  // namespace strata::fleet

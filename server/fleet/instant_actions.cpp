#include "server/fleet/instant_actions.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "drivers/io/json_input.hpp"
#include "server/fleet/map_id.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::fleet {
namespace {

using nlohmann::json;

/// Thrown at the first thing wrong; parse_instant_actions turns it into the message's error.
struct Refusal {
  explicit Refusal(std::string reason, std::string action = {})
      : why(std::move(reason)), action_id(std::move(action)) {}
  std::string why;
  std::string action_id;
};

const json& field(const json& object, const char* name, json::value_t type, const char* type_name,
                  const std::string& action_id = {}) {
  const auto found = object.find(name);
  if (found == object.end())
    throw Refusal{std::string("\"") + name + "\" is missing", action_id};
  const bool number_ok = type == json::value_t::number_float && found->is_number();
  const bool unsigned_ok = type == json::value_t::number_integer && found->is_number_unsigned();
  if (found->type() != type && !number_ok && !unsigned_ok)
    throw Refusal{std::string("\"") + name + "\" must be " + type_name, action_id};
  return *found;
}

std::string string_field(const json& object, const char* name, const std::string& action_id = {}) {
  return field(object, name, json::value_t::string, "a string", action_id).get<std::string>();
}

/// actionParameters as key -> value; a key twice is refused.
std::map<std::string, json> parameters_of(const json& action, const std::string& action_id) {
  std::map<std::string, json> parameters;
  const auto found = action.find("actionParameters");
  if (found == action.end())
    return parameters;
  if (!found->is_array())
    throw Refusal{"\"actionParameters\" must be an array", action_id};
  for (const auto& parameter : *found) {
    if (!parameter.is_object())
      throw Refusal{"an action parameter must be an object with \"key\" and \"value\"", action_id};
    const std::string key = string_field(parameter, "key", action_id);
    const auto value = parameter.find("value");
    if (value == parameter.end() || value->is_null())
      throw Refusal{"the action parameter \"" + key + "\" has no value", action_id};
    if (!parameters.emplace(key, *value).second)
      throw Refusal{"the action parameter \"" + key + "\" is given twice", action_id};
  }
  return parameters;
}

double number_parameter(const std::map<std::string, json>& parameters, const std::string& key,
                        const std::string& action_id) {
  const auto found = parameters.find(key);
  if (found == parameters.end() || !found->second.is_number())
    throw Refusal{"initPosition needs \"" + key + "\" as a number", action_id};
  const double value = found->second.get<double>();
  if (!std::isfinite(value) || std::abs(value) > 1e6)
    throw Refusal{"initPosition's \"" + key + "\" is out of range", action_id};
  return value;
}

InitPosition init_position_of(const std::map<std::string, json>& parameters, const std::string& action_id) {
  InitPosition position;
  position.x = number_parameter(parameters, "x", action_id);
  position.y = number_parameter(parameters, "y", action_id);
  position.theta = number_parameter(parameters, "theta", action_id);
  const auto map_id = parameters.find("mapId");
  if (map_id == parameters.end() || !map_id->second.is_string())
    throw Refusal{"initPosition needs \"mapId\" as a string", action_id};
  position.map_id = map_id->second.get<std::string>();
  if (const auto node = parameters.find("lastNodeId"); node != parameters.end()) {
    if (!node->second.is_string())
      throw Refusal{"initPosition's \"lastNodeId\" must be a string", action_id};
    position.last_node_id = node->second.get<std::string>();
  }
  return position;
}

std::string string_parameter(const std::map<std::string, json>& parameters, const std::string& key,
                             const InstantAction& action, bool optional = false) {
  const auto found = parameters.find(key);
  if (found == parameters.end() && optional)
    return {};
  if (found == parameters.end() || !found->second.is_string())
    throw Refusal{action.action_type + " needs \"" + key + "\" as a string", action.action_id};
  return found->second.get<std::string>();
}

MapAction map_action_of(const std::map<std::string, json>& parameters, const InstantAction& action) {
  MapAction map;
  const std::string map_id = string_parameter(parameters, "mapId", action);
  // A level's mapId or the map's own name: a map's levels are one file, stored, enabled and deleted together.
  if (const auto level = parse_map_id(map_id))
    map.map_name = level->map_name;
  else
    map.map_name = map_id;
  if (!protocol::is_valid_map_name(map.map_name))
    throw Refusal{"\"mapId\" must name a map: NAME or NAME@LEVEL, NAME of A-Z a-z 0-9 . _ -",
                  action.action_id};
  map.map_version = string_parameter(parameters, "mapVersion", action);
  if (!protocol::is_valid_map_name(map.map_version))
    throw Refusal{"\"mapVersion\" must be 1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot",
                  action.action_id};
  if (action.action_type != "downloadMap")
    return map;
  map.download_link = string_parameter(parameters, "mapDownloadLink", action);
  if (map.download_link.size() > 2048 ||
      !(map.download_link.starts_with("http://") || map.download_link.starts_with("https://")))
    throw Refusal{"\"mapDownloadLink\" must be an http:// or https:// URL", action.action_id};
  map.hash = string_parameter(parameters, "mapHash", action, true);
  const bool hex = std::all_of(map.hash.begin(), map.hash.end(),
                               [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
  if (!map.hash.empty() && (map.hash.size() != 64 || !hex))
    throw Refusal{"\"mapHash\" must be a SHA-256: 64 hex digits", action.action_id};
  return map;
}

InstantAction action_of(const json& item) {
  if (!item.is_object())
    throw Refusal{"an action must be an object"};
  InstantAction action;
  action.action_id = string_field(item, "actionId");
  if (action.action_id.empty() || action.action_id.size() > 256)
    throw Refusal{"\"actionId\" must be 1-256 characters"};
  action.action_type = string_field(item, "actionType", action.action_id);
  const std::string blocking = string_field(item, "blockingType", action.action_id);
  if (blocking != "NONE" && blocking != "SOFT" && blocking != "HARD")
    throw Refusal{"\"blockingType\" must be NONE, SOFT or HARD", action.action_id};
  if (const auto description = item.find("actionDescription");
      description != item.end() && !description->is_string())
    throw Refusal{"\"actionDescription\" must be a string", action.action_id};
  const auto& known = supported_instant_actions();
  if (std::find(known.begin(), known.end(), action.action_type) == known.end()) {
    throw Refusal{"the action type \"" + action.action_type.substr(0, 64) +
                      "\" is not one this vehicle carries out (its factsheet lists them)",
                  action.action_id};
  }
  const auto parameters = parameters_of(item, action.action_id);
  if (action.action_type == "initPosition")
    action.init_position = init_position_of(parameters, action.action_id);
  if (action.action_type == "downloadMap" || action.action_type == "enableMap" ||
      action.action_type == "deleteMap")
    action.map = map_action_of(parameters, action);
  return action;
}

}  // namespace

InstantActionsMessage parse_instant_actions(std::string_view payload, const VehicleId& vehicle) {
  InstantActionsMessage message;
  if (payload.size() > kMaxInstantActionsBytes) {
    message.error = "the message is " + std::to_string(payload.size()) + " bytes, more than the " +
                    std::to_string(kMaxInstantActionsBytes) + " taken";
    return message;
  }
  io::JsonInput input = io::parse_json(payload);
  if (!input.ok()) {
    message.error = "not JSON: " + input.error;
    return message;
  }
  const json& document = input.value;
  try {
    if (!document.is_object())
      throw Refusal{"the message must be a JSON object"};
    message.header_id =
        field(document, "headerId", json::value_t::number_integer, "an integer").get<std::int64_t>();
    string_field(document, "timestamp");
    const std::string version = string_field(document, "version");
    if (!version.starts_with("2."))
      throw Refusal{"\"version\" " + version.substr(0, 16) + " is not VDA 5050 2.x"};
    if (string_field(document, "manufacturer") != vehicle.manufacturer ||
        string_field(document, "serialNumber") != vehicle.serial_number)
      throw Refusal{"\"manufacturer\" and \"serialNumber\" name another vehicle"};
    // VDA 5050 2.0.0's JSON schema named the list "instantActions" (the text and 2.1 say "actions"); masters
    // built on that schema (vda-5050-lib) send it so.
    const bool named_as_in_2_0 = version.starts_with("2.0") && !document.contains("actions");
    const json& actions =
        field(document, named_as_in_2_0 ? "instantActions" : "actions", json::value_t::array, "an array");
    if (actions.size() > kMaxInstantActions)
      throw Refusal{"more than " + std::to_string(kMaxInstantActions) + " actions in one message"};
    std::set<std::string> ids;
    for (const auto& item : actions) {
      InstantAction action = action_of(item);
      if (!ids.insert(action.action_id).second)
        throw Refusal{"the actionId is given twice", action.action_id};
      message.actions.push_back(std::move(action));
    }
  } catch (const Refusal& refusal) {
    message.actions.clear();
    message.error = refusal.why;
    message.error_action = refusal.action_id;
  }
  return message;
}

}  // namespace strata::fleet

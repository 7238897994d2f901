#include "server/fleet/order.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "drivers/io/json_input.hpp"
#include "server/fleet/map_id.hpp"

namespace strata::fleet {
namespace {

using nlohmann::json;

constexpr double kPiInSchema = 3.14159265359;  // the 2.1 schema's bound on theta and orientation
constexpr double kMaxCoordinate = 1e6;         // m

/// Thrown at the first thing wrong; parse_order turns it into the message's error.
struct OrderRefusal {
  std::string type;
  std::string why;
  std::vector<std::pair<std::string, std::string>> references;
};

/// Where in the order a check looks: its errors name the node or edge.
struct Place {
  const char* key = nullptr;  ///< "nodeId", "edgeId"; null: the message itself
  std::string id;

  [[noreturn]] void refuse(std::string why, const char* type = "validationError") const {
    OrderRefusal refusal{
        type, (key != nullptr ? std::string(key) + " \"" + id.substr(0, 64) + "\": " : "") + why, {}};
    if (key != nullptr)
      refusal.references.emplace_back(key, id);
    throw refusal;
  }

  const json& field(const json& object, const char* name, bool (json::*is)() const, const char* what) const {
    const auto found = object.find(name);
    if (found == object.end())
      refuse(std::string("\"") + name + "\" is missing");
    if (!((*found).*is)())
      refuse(std::string("\"") + name + "\" must be " + what);
    return *found;
  }

  std::string string(const json& object, const char* name) const {
    return field(object, name, &json::is_string, "a string").get<std::string>();
  }

  std::string id_string(const json& object, const char* name) const {
    std::string value = string(object, name);
    if (value.empty() || value.size() > 256)
      refuse(std::string("\"") + name + "\" must be 1-256 characters");
    return value;
  }

  bool boolean(const json& object, const char* name) const {
    return field(object, name, &json::is_boolean, "true or false").get<bool>();
  }

  std::uint64_t whole(const json& object, const char* name, std::uint64_t max) const {
    const json& value = field(object, name, &json::is_number_integer, "an integer");
    if (!value.is_number_unsigned() || value.get<std::uint64_t>() > max)
      refuse(std::string("\"") + name + "\" must be an integer from 0 to " + std::to_string(max));
    return value.get<std::uint64_t>();
  }

  double number(const json& object, const char* name, double low, double high) const {
    const double value = field(object, name, &json::is_number, "a number").get<double>();
    if (!std::isfinite(value) || value < low || value > high)
      refuse(fmt::format("\"{}\" must be a number from {:g} to {:g}", name, low, high));
    return value;
  }

  /// An optional field, when present, of the type `is` checks.
  bool optional(const json& object, const char* name, bool (json::*is)() const, const char* what) const {
    if (!object.contains(name))
      return false;
    field(object, name, is, what);
    return true;
  }

  /// "actions" is required; Strata carries out no node or edge actions (docs/fleet.md).
  void no_actions(const json& object) const {
    const json& actions = field(object, "actions", &json::is_array, "an array");
    if (actions.empty())
      return;
    OrderRefusal refusal{"orderError",
                         std::string(key) + " \"" + id.substr(0, 64) +
                             "\" has actions: this vehicle carries out no node or edge actions",
                         {{key, id}}};
    if (actions[0].is_object() && actions[0].contains("actionId") && actions[0]["actionId"].is_string())
      refusal.references.emplace_back("actionId", actions[0]["actionId"].get<std::string>());
    throw refusal;
  }
};

NodePosition position_of(const json& node, const Place& place) {
  if (!node.contains("nodePosition"))
    place.refuse("has no nodePosition: this vehicle drives to positions (x, y, mapId)", "orderError");
  const json& object = place.field(node, "nodePosition", &json::is_object, "an object");
  NodePosition position;
  position.x = place.number(object, "x", -kMaxCoordinate, kMaxCoordinate);
  position.y = place.number(object, "y", -kMaxCoordinate, kMaxCoordinate);
  if (object.contains("theta"))
    position.theta = place.number(object, "theta", -kPiInSchema, kPiInSchema);
  if (object.contains("allowedDeviationXY"))
    position.allowed_deviation_xy = place.number(object, "allowedDeviationXY", 0.0, kMaxCoordinate);
  if (object.contains("allowedDeviationTheta"))
    place.number(object, "allowedDeviationTheta", -kPiInSchema, kPiInSchema);
  position.map_id = place.string(object, "mapId");
  place.optional(object, "mapDescription", &json::is_string, "a string");
  if (!parse_map_id(position.map_id))
    place.refuse(
        "\"mapId\" \"" + position.map_id.substr(0, 80) + "\" is no mapId of this vehicle (MAP@LEVEL)",
        "orderError");
  return position;
}

/// What nodes and edges share: the id (`key`), sequenceId, released, the actions' array; `place` names it.
struct Element {
  Place place;
  std::string id;
  std::uint32_t sequence_id = 0;
  bool released = false;
};

Element element_of(const json& item, const char* key, const char* kind) {
  if (!item.is_object())
    Place{}.refuse(std::string("a ") + kind + " must be an object");
  Element element;
  element.id = element.place.id_string(item, key);
  element.place = {key, element.id};
  element.sequence_id = static_cast<std::uint32_t>(
      element.place.whole(item, "sequenceId", std::numeric_limits<std::uint32_t>::max()));
  element.released = element.place.boolean(item, "released");
  element.place.field(item, "actions", &json::is_array, "an array");
  return element;
}

OrderNode node_of(const json& item) {
  const Element element = element_of(item, "nodeId", "node");
  const Place& place = element.place;
  place.optional(item, "nodeDescription", &json::is_string, "a string");
  OrderNode node{element.id, element.sequence_id, element.released, position_of(item, place)};
  place.no_actions(item);
  return node;
}

OrderEdge edge_of(const json& item) {
  const Element element = element_of(item, "edgeId", "edge");
  const Place& place = element.place;
  OrderEdge edge{element.id, element.sequence_id, element.released, {}, {}};
  edge.start_node_id = place.id_string(item, "startNodeId");
  edge.end_node_id = place.id_string(item, "endNodeId");
  for (const char* text : {"edgeDescription", "orientationType", "direction"})
    place.optional(item, text, &json::is_string, "a string");
  for (const char* number : {"maxSpeed", "maxHeight", "minHeight", "maxRotationSpeed", "length"})
    place.optional(item, number, &json::is_number, "a number");
  if (item.contains("orientation"))
    place.number(item, "orientation", -kPiInSchema, kPiInSchema);
  place.optional(item, "rotationAllowed", &json::is_boolean, "true or false");
  for (const char* path : {"trajectory", "corridor"}) {
    if (item.contains(path))
      place.refuse(std::string("has a ") + path + ": this vehicle plans its own way between nodes",
                   "orderError");
  }
  place.no_actions(item);
  return edge;
}

/// Nodes and edges alternate by sequenceId (node, edge, node, ...), each edge between its neighbours, and
/// the base (released) comes first: an edge released only between released nodes, nothing released after
/// something that is not (VDA 5050 2.1, 6.6.1).
void check_graph(const Order& order) {
  const Place message;
  if (order.nodes.empty())
    message.refuse("an order needs at least one node");
  if (order.edges.size() + 1 != order.nodes.size())
    message.refuse("an order needs one edge fewer than nodes");
  const std::uint64_t first = order.nodes.front().sequence_id;
  for (std::size_t i = 0; i < order.nodes.size(); ++i) {
    const OrderNode& node = order.nodes[i];
    const Place place{"nodeId", node.node_id};
    if (node.sequence_id != first + 2 * i)
      place.refuse("\"sequenceId\" " + std::to_string(node.sequence_id) + " breaks the order's sequence (" +
                   std::to_string(first + 2 * i) + " expected)");
    if (i > 0 && node.released && !order.nodes[i - 1].released)
      place.refuse("is released after a node that is not (the base comes first)");
  }
  if (!order.nodes.front().released)
    Place{"nodeId", order.nodes.front().node_id}.refuse("the first node must be released");
  for (std::size_t i = 0; i < order.edges.size(); ++i) {
    const OrderEdge& edge = order.edges[i];
    const Place place{"edgeId", edge.edge_id};
    if (edge.sequence_id != first + 2 * i + 1)
      place.refuse("\"sequenceId\" " + std::to_string(edge.sequence_id) + " breaks the order's sequence (" +
                   std::to_string(first + 2 * i + 1) + " expected)");
    if (edge.start_node_id != order.nodes[i].node_id || edge.end_node_id != order.nodes[i + 1].node_id)
      place.refuse("must lead from the node before it to the node after it");
    if (edge.released != order.nodes[i + 1].released)
      place.refuse(edge.released ? "is released but leads to a node that is not"
                                 : "is not released but leads to a released node");
  }
}

}  // namespace

GoalRequest goal_of(const NodePosition& position) {
  const auto level = parse_map_id(position.map_id);
  return {position.x, position.y, level_height(level ? level->level : 0)};
}

OrderMessage parse_order(std::string_view payload, const VehicleId& vehicle) {
  OrderMessage message;
  const Place at_message;
  try {
    if (payload.size() > kMaxOrderBytes)
      at_message.refuse("the message is " + std::to_string(payload.size()) + " bytes, more than the " +
                        std::to_string(kMaxOrderBytes) + " taken");
    io::JsonInput input = io::parse_json(payload);
    if (!input.ok())
      at_message.refuse("not JSON: " + input.error);
    const json& document = input.value;
    if (!document.is_object())
      at_message.refuse("the message must be a JSON object");
    message.header_id = at_message.whole(document, "headerId", std::numeric_limits<std::uint32_t>::max());
    at_message.string(document, "timestamp");
    const std::string version = at_message.string(document, "version");
    if (!version.starts_with("2."))
      at_message.refuse("\"version\" " + version.substr(0, 16) + " is not VDA 5050 2.x");
    if (at_message.string(document, "manufacturer") != vehicle.manufacturer ||
        at_message.string(document, "serialNumber") != vehicle.serial_number)
      at_message.refuse("\"manufacturer\" and \"serialNumber\" name another vehicle");
    message.order.order_id = at_message.id_string(document, "orderId");
    message.order.update_id =
        at_message.whole(document, "orderUpdateId", std::numeric_limits<std::uint32_t>::max());
    at_message.optional(document, "zoneSetId", &json::is_string, "a string");
    const json& nodes = at_message.field(document, "nodes", &json::is_array, "an array");
    const json& edges = at_message.field(document, "edges", &json::is_array, "an array");
    if (nodes.size() > kMaxOrderNodes)
      at_message.refuse("more than " + std::to_string(kMaxOrderNodes) + " nodes in one order");
    for (const auto& item : nodes)
      message.order.nodes.push_back(node_of(item));
    for (const auto& item : edges)
      message.order.edges.push_back(edge_of(item));
    check_graph(message.order);
  } catch (const OrderRefusal& refusal) {
    message.order.nodes.clear();
    message.order.edges.clear();
    message.error_type = refusal.type;
    message.error = refusal.why;
    message.references = refusal.references;
  }
  return message;
}

}  // namespace strata::fleet

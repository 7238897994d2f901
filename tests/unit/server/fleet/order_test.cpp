// VDA 5050 2.1 orders (issue 61): an order is checked whole (the schema's fields and types, nodes and edges
// alternating by sequenceId, the base first, what Strata can carry out), and the vehicle's order follows the
// update rules of 6.6: a higher orderUpdateId stitched at the base's last node extends it, a lower one is
// refused, the same one ignored, a new orderId refused while the order runs.
#include "server/fleet/order.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server/fleet/order_progress.hpp"

namespace strata::fleet {
namespace {

using nlohmann::json;

const VehicleId kOrderVehicle{"uagv", "Strata", "robot-1"};

json order_node(const std::string& id, int sequence, bool released = true, double x = 1.0) {
  return {{"nodeId", id},
          {"sequenceId", sequence},
          {"released", released},
          {"nodePosition", {{"x", x}, {"y", 2.0}, {"theta", 0.5}, {"mapId", "yard.smls@0"}}},
          {"actions", json::array()}};
}

json order_edge(const std::string& from, const std::string& to, int sequence, bool released = true) {
  return {{"edgeId", from + "-" + to}, {"sequenceId", sequence}, {"released", released},
          {"startNodeId", from},       {"endNodeId", to},        {"actions", json::array()}};
}

/// Nodes `ids` from sequenceId `first` on, the first `released` of them in the base.
json order_json(const std::vector<std::string>& ids, std::size_t released, int first = 0, int update = 0,
                const std::string& order_id = "order-1") {
  json nodes = json::array();
  json edges = json::array();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    nodes.push_back(
        order_node(ids[i], first + 2 * static_cast<int>(i), i < released, static_cast<double>(i)));
    if (i > 0)
      edges.push_back(order_edge(ids[i - 1], ids[i], first + 2 * static_cast<int>(i) - 1, i < released));
  }
  return {{"headerId", 3},
          {"timestamp", "2026-12-02T15:00:00.00Z"},
          {"version", "2.1.0"},
          {"manufacturer", "Strata"},
          {"serialNumber", "robot-1"},
          {"orderId", order_id},
          {"orderUpdateId", update},
          {"nodes", std::move(nodes)},
          {"edges", std::move(edges)}};
}

Order parsed(const json& message) {
  const OrderMessage result = parse_order(message.dump(), kOrderVehicle);
  EXPECT_TRUE(result.ok()) << result.error;
  return result.order;
}

TEST(Order, AWellFormedOrderIsTakenWithItsBaseAndHorizon) {
  const OrderMessage message = parse_order(order_json({"a", "b", "c", "d"}, 3).dump(), kOrderVehicle);
  ASSERT_TRUE(message.ok()) << message.error;
  EXPECT_EQ(message.header_id, 3u);
  ASSERT_EQ(message.order.nodes.size(), 4u);
  ASSERT_EQ(message.order.edges.size(), 3u);
  EXPECT_EQ(message.order.nodes[2].sequence_id, 4u);
  EXPECT_TRUE(message.order.nodes[2].released);
  EXPECT_FALSE(message.order.nodes[3].released);
  EXPECT_FALSE(message.order.edges[2].released);
  EXPECT_EQ(message.order.nodes[1].position.map_id, "yard.smls@0");
  EXPECT_DOUBLE_EQ(*message.order.nodes[1].position.theta, 0.5);
}

TEST(Order, WrongTypesAndBrokenSequencesAreValidationErrorsNamingThePlace) {
  const auto refused = [](const json& message) { return parse_order(message.dump(), kOrderVehicle); };
  json wrong = order_json({"a", "b"}, 2);
  wrong["nodes"][1]["nodePosition"]["x"] = "1";
  OrderMessage message = refused(wrong);
  EXPECT_EQ(message.error_type, "validationError");
  EXPECT_NE(message.error.find("\"x\""), std::string::npos) << message.error;
  ASSERT_EQ(message.references.size(), 1u);
  EXPECT_EQ(message.references[0], (std::pair<std::string, std::string>{"nodeId", "b"}));
  EXPECT_TRUE(message.order.nodes.empty());

  json gap = order_json({"a", "b", "c"}, 3);
  gap["nodes"][2]["sequenceId"] = 6;
  EXPECT_NE(refused(gap).error.find("sequence"), std::string::npos);
  json crossed = order_json({"a", "b"}, 2);
  crossed["edges"][0]["endNodeId"] = "z";
  EXPECT_EQ(refused(crossed).error_type, "validationError");
  json released_after_horizon = order_json({"a", "b", "c"}, 1);
  released_after_horizon["nodes"][2]["released"] = true;
  EXPECT_NE(refused(released_after_horizon).error.find("base comes first"), std::string::npos);
  json edges_missing = order_json({"a", "b"}, 2);
  edges_missing["edges"] = json::array();
  EXPECT_EQ(refused(edges_missing).error_type, "validationError");
  json theta = order_json({"a"}, 1);
  theta["nodes"][0]["nodePosition"]["theta"] = 4.0;
  EXPECT_EQ(refused(theta).error_type, "validationError");
  json other_vehicle = order_json({"a"}, 1);
  other_vehicle["serialNumber"] = "robot-2";
  EXPECT_EQ(refused(other_vehicle).error_type, "validationError");
  EXPECT_EQ(parse_order("{\"orderId\": [", kOrderVehicle).error_type, "validationError");
  EXPECT_EQ(parse_order(std::string(kMaxOrderBytes + 1, ' '), kOrderVehicle).error_type, "validationError");
}

TEST(Order, WhatStrataCannotCarryOutIsAnOrderError) {
  const auto refused = [](const json& message) { return parse_order(message.dump(), kOrderVehicle); };
  json no_position = order_json({"a", "b"}, 2);
  no_position["nodes"][1].erase("nodePosition");
  EXPECT_EQ(refused(no_position).error_type, "orderError");
  json with_action = order_json({"a", "b"}, 2);
  with_action["nodes"][1]["actions"] = {
      {{"actionId", "lift-1"}, {"actionType", "pick"}, {"blockingType", "HARD"}}};
  const OrderMessage action = refused(with_action);
  EXPECT_EQ(action.error_type, "orderError");
  EXPECT_EQ(action.references.back(), (std::pair<std::string, std::string>{"actionId", "lift-1"}));
  json trajectory = order_json({"a", "b"}, 2);
  trajectory["edges"][0]["trajectory"] = {
      {"degree", 1}, {"knotVector", json::array()}, {"controlPoints", json::array()}};
  EXPECT_EQ(refused(trajectory).error_type, "orderError");
  json foreign_map_id = order_json({"a"}, 1);
  foreign_map_id["nodes"][0]["nodePosition"]["mapId"] = "warehouse-3";
  EXPECT_EQ(refused(foreign_map_id).error_type, "orderError");
}

TEST(Order, ANodeIsDrivenToOnItsMapIdsLevel) {
  NodePosition deck{12.0, -3.0, std::nullopt, 0.0, "campus.smls@1"};
  const GoalRequest goal = goal_of(deck);
  EXPECT_DOUBLE_EQ(goal.x, 12.0);
  EXPECT_DOUBLE_EQ(goal.y, -3.0);
  EXPECT_DOUBLE_EQ(goal.z.value(), 2.5) << "level 1: the surface nearest 2.5 m";
  deck.map_id = "plant.smls@-1";
  EXPECT_DOUBLE_EQ(goal_of(deck).z.value(), -2.5);
}

TEST(OrderProgress, NodesAndEdgesLeaveTheStatesAsTheyArePassed) {
  OrderProgress progress;
  const Order order = parsed(order_json({"a", "b", "c"}, 3));
  ASSERT_EQ(progress.judge(order).verdict, OrderVerdict::kNew);
  progress.start(order);
  EXPECT_EQ(progress.last_node_id(), "a");  // the first node is where the vehicle stands
  EXPECT_EQ(progress.nodes().size(), 2u);
  EXPECT_EQ(progress.edges().size(), 2u);
  ASSERT_NE(progress.next_base_node(), nullptr);
  EXPECT_EQ(progress.next_base_node()->node_id, "b");
  progress.pass_next_node();
  EXPECT_EQ(progress.last_node_id(), "b");
  EXPECT_EQ(progress.last_node_sequence_id(), 2u);
  EXPECT_EQ(progress.edges().size(), 1u);
  EXPECT_EQ(progress.edges().front().edge_id, "b-c");
  progress.pass_next_node();
  EXPECT_FALSE(progress.running());
  EXPECT_TRUE(progress.edges().empty());
  EXPECT_EQ(progress.next_base_node(), nullptr);
}

TEST(OrderProgress, AnUpdateStitchedAtTheBasesLastNodeExtendsItOthersAreRefused) {
  OrderProgress progress;
  progress.start(parsed(order_json({"a", "b", "c"}, 2)));  // base a-b, horizon c
  progress.pass_next_node();
  EXPECT_EQ(progress.next_base_node(), nullptr) << "the horizon is not driven";
  EXPECT_TRUE(progress.running());

  const OrderDecision wrong_stitch = progress.judge(parsed(order_json({"c", "d"}, 2, 4, 1)));
  EXPECT_EQ(wrong_stitch.verdict, OrderVerdict::kRefused);
  EXPECT_EQ(wrong_stitch.error_type, "orderUpdateError");
  const Order update = parsed(order_json({"b", "c", "d"}, 3, 2, 1));
  ASSERT_EQ(progress.judge(update).verdict, OrderVerdict::kUpdate);
  progress.extend(update);
  EXPECT_EQ(progress.update_id(), 1u);
  ASSERT_EQ(progress.nodes().size(), 2u);
  EXPECT_EQ(progress.nodes()[0].node_id, "c");
  EXPECT_TRUE(progress.nodes()[0].released);
  ASSERT_EQ(progress.edges().size(), 2u);
  EXPECT_EQ(progress.edges()[0].edge_id, "b-c");

  EXPECT_EQ(progress.judge(update).verdict, OrderVerdict::kResent);
  const OrderDecision stale = progress.judge(parsed(order_json({"b", "c"}, 2, 2, 0)));
  EXPECT_EQ(stale.verdict, OrderVerdict::kRefused);
  EXPECT_EQ(stale.error_type, "orderUpdateError");
  const OrderDecision busy = progress.judge(parsed(order_json({"x", "y"}, 2, 0, 0, "order-2")));
  EXPECT_EQ(busy.verdict, OrderVerdict::kRefused);
  EXPECT_EQ(busy.error_type, "orderError");

  progress.pass_next_node();
  progress.pass_next_node();
  EXPECT_FALSE(progress.running());
  EXPECT_EQ(progress.last_node_id(), "d");
  EXPECT_EQ(progress.judge(parsed(order_json({"x", "y"}, 2, 0, 0, "order-2"))).verdict, OrderVerdict::kNew);
  // A finished order goes on from its last node (6.6.2, step 8).
  EXPECT_EQ(progress.judge(parsed(order_json({"d", "e"}, 2, 6, 2))).verdict, OrderVerdict::kUpdate);
}

TEST(OrderProgress, ACancelledOrderTakesNoUpdateButANewOrder) {
  OrderProgress progress;
  progress.start(parsed(order_json({"a", "b", "c"}, 3)));
  progress.cancel();
  EXPECT_FALSE(progress.running());
  EXPECT_EQ(progress.order_id(), "order-1");
  EXPECT_EQ(progress.judge(parsed(order_json({"c", "d"}, 2, 4, 1))).verdict, OrderVerdict::kRefused);
  EXPECT_EQ(progress.judge(parsed(order_json({"x", "y"}, 2, 0, 0, "order-2"))).verdict, OrderVerdict::kNew);
}

}  // namespace
}  // namespace strata::fleet

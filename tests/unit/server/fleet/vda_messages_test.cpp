// What the vehicle sends, field by field where the schemas leave room (the fleet tests check every message
// against the 2.1.0 schemas themselves).
#include "server/fleet/vda_messages.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <string>

namespace strata::fleet {
namespace {

TEST(VdaMessages, TimestampsAreUtcIsoWithMilliseconds) {
  const auto time = std::chrono::system_clock::time_point(std::chrono::milliseconds(1796224800123));
  EXPECT_EQ(iso_timestamp(time), "2026-12-02T15:20:00.123Z");
  EXPECT_TRUE(std::regex_match(iso_timestamp(std::chrono::system_clock::now()),
                               std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)")));
}

TEST(VdaMessages, HeadersCountPerTopicAndNameTheVehicle) {
  const VehicleId id{"uagv", "Strata", "robot-1"};
  EXPECT_EQ(id.topic("state"), "uagv/v2/Strata/robot-1/state");
  HeaderStamp state(id);
  HeaderStamp visualization(id);
  const auto now = std::chrono::system_clock::now();
  EXPECT_EQ(state.stamp(nlohmann::json::object(), now)["headerId"], 0);
  EXPECT_EQ(state.stamp(nlohmann::json::object(), now)["headerId"], 1);
  const auto first = visualization.stamp(nlohmann::json::object(), now);
  EXPECT_EQ(first["headerId"], 0);
  EXPECT_EQ(first["version"], "2.1.0");
  EXPECT_EQ(first["serialNumber"], "robot-1");
}

TEST(VdaMessages, TheStateSaysWhatItKnowsAndLeavesOutWhatItDoesNot) {
  VehicleReport report;
  EXPECT_FALSE(state_body(report).contains("agvPosition")) << "no pose before the first sample";
  report.position = AgvPosition{1.0, 2.0, 0.5, "yard.smls@0", true, 0.8, std::nullopt};
  report.errors.push_back({"validationError", "WARNING", "why", {{"topic", "instantActions"}}});
  report.actions.push_back({"a-1", "stateRequest", "FINISHED", ""});
  const auto body = state_body(report);
  EXPECT_EQ(body["agvPosition"]["mapId"], "yard.smls@0");
  EXPECT_EQ(body["agvPosition"]["localizationScore"], 0.8);
  EXPECT_FALSE(body["agvPosition"].contains("deviationRange"));
  EXPECT_EQ(body["errors"][0]["errorReferences"][0]["referenceKey"], "topic");
  EXPECT_EQ(body["actionStates"][0]["actionStatus"], "FINISHED");
  EXPECT_FALSE(body["actionStates"][0].contains("resultDescription"));
  EXPECT_EQ(body["safetyState"]["eStop"], "NONE");
  EXPECT_EQ(body["orderId"], "") << "no order yet";
  EXPECT_TRUE(body["nodeStates"].empty());
}

TEST(VdaMessages, TheStateCarriesTheOrdersIdsAndWhatIsLeftOfIt) {
  VehicleReport report;
  report.order_id = "order-1";
  report.order_update_id = 2;
  report.last_node_id = "b";
  report.last_node_sequence_id = 2;
  report.node_states.push_back({"c", 4, true, 1.5, -2.0, std::nullopt, "yard.smls@1"});
  report.node_states.push_back({"d", 6, false, 3.0, -2.0, 0.25, "yard.smls@1"});
  report.edge_states.push_back({"b-c", 3, true});
  report.edge_states.push_back({"c-d", 5, false});
  const auto body = state_body(report);
  EXPECT_EQ(body["orderId"], "order-1");
  EXPECT_EQ(body["orderUpdateId"], 2);
  EXPECT_EQ(body["lastNodeId"], "b");
  EXPECT_EQ(body["lastNodeSequenceId"], 2);
  ASSERT_EQ(body["nodeStates"].size(), 2u);
  EXPECT_EQ(body["nodeStates"][0]["nodePosition"]["mapId"], "yard.smls@1");
  EXPECT_FALSE(body["nodeStates"][0]["nodePosition"].contains("theta"));
  EXPECT_EQ(body["nodeStates"][1]["nodePosition"]["theta"], 0.25);
  EXPECT_EQ(body["nodeStates"][1]["released"], false);
  EXPECT_EQ(body["edgeStates"][1]["edgeId"], "c-d");
  EXPECT_EQ(body["edgeStates"][1]["sequenceId"], 5);
}

}  // namespace
}  // namespace strata::fleet

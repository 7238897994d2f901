// The instantActions a master sends are checked whole before any is carried out (issue 61): a message with
// wrong types, an unknown action, a huge payload or nesting past the bound is refused with a reason.
#include "server/fleet/instant_actions.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

namespace strata::fleet {
namespace {

using nlohmann::json;

const VehicleId kVehicle{"uagv", "Strata", "robot-1"};

json message_with(json actions) {
  return {{"headerId", 7},
          {"timestamp", "2026-12-02T15:00:00.00Z"},
          {"version", "2.1.0"},
          {"manufacturer", "Strata"},
          {"serialNumber", "robot-1"},
          {"actions", std::move(actions)}};
}

json init_position(json x = 1.5) {
  return {{"actionId", "init-1"},
          {"actionType", "initPosition"},
          {"blockingType", "HARD"},
          {"actionParameters",
           {{{"key", "x"}, {"value", std::move(x)}},
            {{"key", "y"}, {"value", -2.0}},
            {{"key", "theta"}, {"value", 0.5}},
            {{"key", "mapId"}, {"value", "yard@0"}},
            {{"key", "lastNodeId"}, {"value", ""}}}}};
}

TEST(InstantActions, AWellFormedMessageIsTakenWithItsParameters) {
  const json state_request{{"actionId", "s-1"}, {"actionType", "stateRequest"}, {"blockingType", "NONE"}};
  const auto message = parse_instant_actions(message_with({init_position(), state_request}).dump(), kVehicle);
  ASSERT_TRUE(message.ok()) << message.error;
  ASSERT_EQ(message.actions.size(), 2U);
  ASSERT_TRUE(message.actions[0].init_position);
  EXPECT_DOUBLE_EQ(message.actions[0].init_position->x, 1.5);
  EXPECT_DOUBLE_EQ(message.actions[0].init_position->y, -2.0);
  EXPECT_EQ(message.actions[0].init_position->map_id, "yard@0");
  EXPECT_EQ(message.actions[1].action_type, "stateRequest");
  EXPECT_EQ(message.header_id, 7U);
}

TEST(InstantActions, AVersion2_0MastersListIsTakenUnderItsSchemasName) {
  json message = message_with(json::array());
  message.erase("actions");
  message["version"] = "2.0.0";
  message["instantActions"] = {init_position()};
  const auto taken = parse_instant_actions(message.dump(), kVehicle);
  ASSERT_TRUE(taken.ok()) << taken.error;
  EXPECT_EQ(taken.actions.size(), 1U);
  message["version"] = "2.1.0";
  EXPECT_FALSE(parse_instant_actions(message.dump(), kVehicle).ok()) << "2.1 names it \"actions\"";
}

TEST(InstantActions, WrongTypesAreRefusedWithTheActionNamed) {
  const auto message = parse_instant_actions(message_with({init_position("1.5")}).dump(), kVehicle);
  EXPECT_FALSE(message.ok());
  EXPECT_TRUE(message.actions.empty());
  EXPECT_NE(message.error.find("\"x\""), std::string::npos) << message.error;
  EXPECT_EQ(message.error_action, "init-1");

  json header_wrong = message_with(json::array());
  header_wrong["headerId"] = "7";
  EXPECT_FALSE(parse_instant_actions(header_wrong.dump(), kVehicle).ok());
  json actions_wrong = message_with(json::array());
  actions_wrong["actions"] = json::object();
  EXPECT_FALSE(parse_instant_actions(actions_wrong.dump(), kVehicle).ok());
}

TEST(InstantActions, AnUnknownActionRefusesTheWholeMessage) {
  const json lift{{"actionId", "l-1"}, {"actionType", "lift"}, {"blockingType", "HARD"}};
  const auto message = parse_instant_actions(message_with({init_position(), lift}).dump(), kVehicle);
  EXPECT_FALSE(message.ok());
  EXPECT_TRUE(message.actions.empty()) << "nothing of a refused message is carried out";
  EXPECT_NE(message.error.find("lift"), std::string::npos) << message.error;
  EXPECT_EQ(message.error_action, "l-1");
}

TEST(InstantActions, HugeDeepOrForeignMessagesAreRefused) {
  EXPECT_FALSE(parse_instant_actions(std::string(kMaxInstantActionsBytes + 1, ' '), kVehicle).ok());
  EXPECT_FALSE(parse_instant_actions(std::string(10000, '[') + std::string(10000, ']'), kVehicle).ok());
  EXPECT_FALSE(parse_instant_actions("{\"headerId\": 1,", kVehicle).ok());
  json other = message_with(json::array());
  other["serialNumber"] = "robot-2";
  EXPECT_FALSE(parse_instant_actions(other.dump(), kVehicle).ok());
  json duplicated = message_with({init_position(), init_position()});
  EXPECT_FALSE(parse_instant_actions(duplicated.dump(), kVehicle).ok());
  json infinite = message_with({init_position(1e300)});
  EXPECT_FALSE(parse_instant_actions(infinite.dump(), kVehicle).ok());
}

}  // namespace
}  // namespace strata::fleet

namespace strata::fleet {
namespace {

json map_action(const std::string& type, json parameters) {
  return {{"actionId", type + "-1"},
          {"actionType", type},
          {"blockingType", "NONE"},
          {"actionParameters", std::move(parameters)}};
}

TEST(InstantActions, MapActionsNameTheMapByItsIdOrName) {
  const std::string hash(64, 'a');
  const auto message = parse_instant_actions(
      message_with({map_action("downloadMap", {{{"key", "mapId"}, {"value", "yard.smls@1"}},
                                               {{"key", "mapVersion"}, {"value", "3"}},
                                               {{"key", "mapDownloadLink"}, {"value", "http://a:8080/m"}},
                                               {{"key", "mapHash"}, {"value", hash}}}),
                    map_action("enableMap", {{{"key", "mapId"}, {"value", "yard.smls"}},
                                             {{"key", "mapVersion"}, {"value", "3"}}})})
          .dump(),
      kVehicle);
  ASSERT_TRUE(message.ok()) << message.error;
  ASSERT_TRUE(message.actions[0].map);
  EXPECT_EQ(message.actions[0].map->map_name, "yard.smls");  // all of a map's levels are one file
  EXPECT_EQ(message.actions[0].map->map_version, "3");
  EXPECT_EQ(message.actions[0].map->download_link, "http://a:8080/m");
  EXPECT_EQ(message.actions[0].map->hash, hash);
  EXPECT_EQ(message.actions[1].map->map_name, "yard.smls");
}

TEST(InstantActions, MapActionsWithBadParametersAreRefused) {
  const auto refused = [](json parameters, const std::string& expected) {
    const auto message = parse_instant_actions(
        message_with({map_action("downloadMap", std::move(parameters))}).dump(), kVehicle);
    EXPECT_FALSE(message.ok());
    EXPECT_NE(message.error.find(expected), std::string::npos) << message.error;
  };
  const json id{{"key", "mapId"}, {"value", "yard@0"}};
  const json version{{"key", "mapVersion"}, {"value", "1"}};
  const json link{{"key", "mapDownloadLink"}, {"value", "http://host/m"}};
  refused({id, version}, "mapDownloadLink");
  refused({id, version, {{"key", "mapDownloadLink"}, {"value", "file:///etc/passwd"}}}, "http://");
  refused({id, version, link, {{"key", "mapHash"}, {"value", "abc"}}}, "64 hex");
  refused({{{"key", "mapId"}, {"value", "../../etc@0"}}, version, link}, "mapId");
  refused({id, {{"key", "mapVersion"}, {"value", "../1"}}, link}, "mapVersion");
  refused({id, {{"key", "mapVersion"}, {"value", 1}}, link}, "mapVersion");
}

}  // namespace
}  // namespace strata::fleet

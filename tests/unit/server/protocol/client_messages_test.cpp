#include "server/protocol/client_messages.hpp"

#include <gtest/gtest.h>

namespace strata::protocol {
namespace {

TEST(ClientMessages, ValidRequests) {
  auto goal = parse_client_message(R"({"op":"set_goal","x":1.5,"y":-2,"id":7})");
  ASSERT_TRUE(goal.request);
  const auto& set_goal = std::get<SetGoalRequest>(*goal.request);
  EXPECT_DOUBLE_EQ(set_goal.goal.x, 1.5);
  EXPECT_DOUBLE_EQ(set_goal.goal.y, -2.0);
  EXPECT_FALSE(set_goal.goal.z);
  EXPECT_EQ(goal.id, 7);
  EXPECT_TRUE(needs_operator(*goal.request));

  auto level = parse_client_message(R"({"op":"set_goal","x":1,"y":2,"z":3.2})");
  ASSERT_TRUE(level.request);
  EXPECT_DOUBLE_EQ(*std::get<SetGoalRequest>(*level.request).goal.z, 3.2);

  auto teleop = parse_client_message(R"({"op":"teleop","v":0.5,"w":-0.3})");
  ASSERT_TRUE(teleop.request);
  EXPECT_DOUBLE_EQ(std::get<TeleopRequest>(*teleop.request).w, -0.3);

  auto subscribe = parse_client_message(R"({"op":"subscribe","streams":["pose","tiles"]})");
  ASSERT_TRUE(subscribe.request);
  const StreamSet streams = std::get<SubscribeRequest>(*subscribe.request).streams;
  EXPECT_TRUE(contains(streams, Stream::kPose));
  EXPECT_TRUE(contains(streams, Stream::kTiles));
  EXPECT_FALSE(contains(streams, Stream::kOccupancy));
  EXPECT_FALSE(needs_operator(*subscribe.request));

  EXPECT_TRUE(parse_client_message(R"({"op":"cancel_goal"})").request);
  EXPECT_TRUE(parse_client_message(R"({"op":"save_map","name":"hall-2.strata"})").request);
  EXPECT_TRUE(parse_client_message(R"({"op":"load_map","name":"hall-2.strata"})").request);
  const auto localize = parse_client_message(R"({"op":"load_map","name":"hall-2.strata","mode":"localize"})");
  ASSERT_TRUE(localize.request);
  EXPECT_EQ(std::get<LoadMapRequest>(*localize.request).mode, MapMode::kLocalize);
  EXPECT_TRUE(parse_client_message(R"({"op":"ping","id":"a"})").request);
}

TEST(ClientMessages, TeleopCarriesItsSequenceAndSendingTime) {
  const auto stamped = parse_client_message(R"({"op":"teleop","v":0.5,"w":0,"seq":12,"t":81234567.5})");
  ASSERT_TRUE(stamped.request);
  const auto& teleop = std::get<TeleopRequest>(*stamped.request);
  ASSERT_TRUE(teleop.stamp);
  EXPECT_EQ(teleop.stamp->seq, 12U);
  EXPECT_DOUBLE_EQ(teleop.stamp->sent_ms, 81234567.5);
  EXPECT_TRUE(teleop.moves());
  const auto stop = parse_client_message(R"({"op":"teleop","v":0,"w":0})");
  ASSERT_TRUE(stop.request);
  EXPECT_FALSE(std::get<TeleopRequest>(*stop.request).stamp);
  EXPECT_FALSE(std::get<TeleopRequest>(*stop.request).moves());
  for (const char* half :
       {R"({"op":"teleop","v":0.5,"w":0,"seq":1})", R"({"op":"teleop","v":0.5,"w":0,"t":1})",
        R"({"op":"teleop","v":0.5,"w":0,"seq":-1,"t":1})", R"({"op":"teleop","v":0.5,"w":0,"seq":1.5,"t":1})",
        R"({"op":"teleop","v":0.5,"w":0,"seq":1,"t":"now"})"}) {
    EXPECT_EQ(parse_client_message(half).error, ErrorCode::kBadParams) << half;
  }
}

TEST(ClientMessages, JsonNestedTooDeepIsRefusedAndNeverEchoed) {
  const std::string deep =
      R"({"op":"subscribe","streams":[)" + std::string(100000, '[') + std::string(100000, ']') + "]}";
  const auto refused = parse_client_message(deep);
  EXPECT_FALSE(refused.request);
  EXPECT_EQ(refused.error, ErrorCode::kBadJson);
  EXPECT_EQ(refused.error_message, "message is nested deeper than 64 levels");
  // Within the bound, an unknown item is named briefly.
  const auto item =
      parse_client_message(R"({"op":"subscribe","streams":[")" + std::string(5000, 'x') + R"("]})");
  EXPECT_EQ(item.error, ErrorCode::kBadParams);
  EXPECT_LT(item.error_message.size(), 200U);
}

struct Refusal {
  const char* text;
  ErrorCode code;
};

TEST(ClientMessages, EveryBadMessageGetsItsCode) {
  const Refusal refusals[] = {
      {"{", ErrorCode::kBadJson},
      {"[]", ErrorCode::kBadMessage},
      {R"({"x":1})", ErrorCode::kBadMessage},
      {R"({"op":3})", ErrorCode::kBadMessage},
      {R"({"op":"fly"})", ErrorCode::kUnknownOp},
      {R"({"op":"set_goal","x":1})", ErrorCode::kBadParams},
      {R"({"op":"set_goal","x":"1","y":2})", ErrorCode::kBadParams},
      {R"({"op":"set_goal","x":1,"y":2,"speed":3})", ErrorCode::kBadParams},
      {R"({"op":"set_goal","x":1e300,"y":2})", ErrorCode::kBadParams},
      {R"({"op":"set_goal","x":1,"y":2,"z":null})", ErrorCode::kBadParams},
      {R"({"op":"teleop","v":10,"w":0})", ErrorCode::kBadParams},
      {R"({"op":"teleop","v":0.1})", ErrorCode::kBadParams},
      {R"({"op":"save_map","name":"../x"})", ErrorCode::kBadParams},
      {R"({"op":"save_map","name":".hidden"})", ErrorCode::kBadParams},
      {R"({"op":"save_map","name":""})", ErrorCode::kBadParams},
      {R"({"op":"load_map"})", ErrorCode::kBadParams},
      {R"({"op":"load_map","name":"a","mode":"navigate"})", ErrorCode::kBadParams},
      {R"({"op":"load_map","name":"a","mode":null})", ErrorCode::kBadParams},
      {R"({"op":"subscribe","streams":["pose","weather"]})", ErrorCode::kBadParams},
      {R"({"op":"subscribe","streams":"pose"})", ErrorCode::kBadParams},
      {R"({"op":"ping","id":{"a":1}})", ErrorCode::kBadParams},
  };
  for (const auto& refusal : refusals) {
    const auto parsed = parse_client_message(refusal.text);
    EXPECT_FALSE(parsed.request) << refusal.text;
    EXPECT_EQ(parsed.error, refusal.code) << refusal.text << ": " << parsed.error_message;
    EXPECT_FALSE(parsed.error_message.empty());
  }
}

TEST(ClientMessages, ALimitIsSaidAsPeopleWriteIt) {
  const auto parsed = parse_client_message(R"({"op":"teleop","v":10,"w":0})");
  EXPECT_NE(parsed.error_message.find("\"v\" must be a finite number from -"), std::string::npos)
      << parsed.error_message;
  EXPECT_EQ(parsed.error_message.find("000000"), std::string::npos) << parsed.error_message;
  EXPECT_EQ(parsed.error_message.find("+-"), std::string::npos) << parsed.error_message;
}

TEST(ClientMessages, MapNames) {
  EXPECT_TRUE(is_valid_map_name("a"));
  EXPECT_TRUE(is_valid_map_name("campus_2026-11-21.strata"));
  EXPECT_FALSE(is_valid_map_name("a/b"));
  EXPECT_FALSE(is_valid_map_name(".."));
  EXPECT_FALSE(is_valid_map_name(std::string(65, 'a')));
}

}  // namespace
}  // namespace strata::protocol

// The real strata process over a real WebSocket: the hello, the late joiner's state, the live pose
// stream, and the handling of bad client input.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

class WebSocketStream : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new ServerProcess({"--time-scale", "4", "--pose-rate", "25"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static ServerProcess* server_;
};
ServerProcess* WebSocketStream::server_ = nullptr;

TEST(ProtocolSchemas, RejectWhatTheyShould) {
  // The schema checks in every read are only worth something if they can fail.
  EXPECT_FALSE(protocol_schemas().violations("ws-server", "pose", {{"op", "pose"}}).empty());
  EXPECT_FALSE(protocol_schemas().server_message_violations({{"op", "hello"}, {"server", "other"}}).empty());
  EXPECT_FALSE(protocol_schemas().violations("rest", "error", {{"error", {{"code", "made_up"}}}}).empty());
  EXPECT_THROW(protocol_schemas().server_message_violations({{"op", "no_such_op"}}), std::runtime_error);
}

TEST_F(WebSocketStream, HandshakeEchoesTheSubprotocol) {
  WsClient client(port());
  EXPECT_EQ(client.handshake_response()[http::field::sec_websocket_protocol], "strata.v1");
}

TEST_F(WebSocketStream, HelloComesFirst) {
  WsClient client(port());
  const auto hello = client.read();
  EXPECT_EQ(hello["op"], "hello");
  EXPECT_EQ(hello["protocol"], "strata.v1");
  EXPECT_EQ(hello["protocol_version"], 1);
}

TEST_F(WebSocketStream, LateJoinerGetsTheWorldAndPoseAtOnce) {
  WsClient client(port());
  std::vector<std::string> ops;
  for (int i = 0; i < 4; ++i)
    ops.push_back(client.read()["op"]);
  EXPECT_EQ(ops, (std::vector<std::string>{"hello", "sim_world", "status", "pose"}));
}

TEST_F(WebSocketStream, PosesArriveAndChange) {
  WsClient client(port());
  const auto first = client.read_op("pose");
  double last_stamp = first["stamp"];
  bool moved = false;
  // The robot may be standing for a stop-and-go scan: read until it has moved (bounded, not timed).
  for (int i = 0; i < 1500 && !moved; ++i) {
    const auto pose = client.read_op("pose");
    for (const char* key : {"x", "y", "z", "roll", "pitch", "yaw", "stamp"}) {
      ASSERT_TRUE(pose[key].is_number()) << key;
    }
    EXPECT_GT(pose["stamp"].get<double>(), last_stamp);  // each frame is a newer pose
    last_stamp = pose["stamp"];
    moved = moved || pose["x"] != first["x"] || pose["y"] != first["y"];
  }
  EXPECT_TRUE(moved);
}

TEST_F(WebSocketStream, ScansAreRegisteredAndCorrectThePose) {
  // The first stop-and-go scan is taken at the start; once one is registered, the pose rests on it.
  WsClient client(port());
  bool registered = false;
  for (int i = 0; i < 3000 && !registered; ++i) {
    const auto message = client.read();
    registered = message["op"] == "pose" && message["source"] == "registration";
  }
  EXPECT_TRUE(registered);
  // Status reports registrations once there have been two scans (the first only starts the map).
  // read() checks each message against its schema: the localization state and its reason are required.
  bool counted = false;
  nlohmann::json streamed;
  for (int i = 0; i < 6000 && !counted; ++i) {
    streamed = client.read();
    counted = streamed["op"] == "status" && streamed["registration"]["scans"] >= 2 &&
              streamed["registration"].contains("last");
  }
  ASSERT_TRUE(counted);
  // After registered scans the state says how they went, not that there was none yet.
  EXPECT_NE(streamed["localization"]["reason"], "no scan yet: position from odometry only")
      << streamed.dump();
  const auto status = nlohmann::json::parse(http_get(port(), "/api/v1/status").body());
  expect_schema("rest", "status", status);
  EXPECT_GE(status["registration"]["scans"], 2);
  // /metrics: one series per state, exactly one of them 1.
  const std::string metrics = http_get(port(), "/metrics").body();
  int current = 0;
  for (const char* state : {"ok", "degraded", "lost"}) {
    const std::string series = std::string("strata_localization_state{state=\"") + state + "\"} ";
    const auto at = metrics.find(series);
    ASSERT_NE(at, std::string::npos) << series << " in\n" << metrics;
    current += metrics.compare(at + series.size(), 2, "1\n") == 0 ? 1 : 0;
  }
  EXPECT_EQ(current, 1) << metrics;
}

TEST_F(WebSocketStream, DefaultWorldIsTheCampus) {
  WsClient client(port());
  const auto world = client.read_op("sim_world");  // read() checks it against its schema
  EXPECT_EQ(world["name"], "campus");
  EXPECT_GT(world["boxes"].size(), 10u);
  EXPECT_GE(world["ramps"].size(), 2u);  // the entrance ramp and the bridge ramp
  EXPECT_TRUE(world.contains("terrain"));
  for (const auto& box : world["boxes"]) {
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_GT(box["size"][axis], 0.0);
  }
}

TEST_F(WebSocketStream, BadMessagesGetCodedErrorsAndTheStreamGoesOn) {
  WsClient client(port());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"this is not json", "bad_json"},
      {"[1,2,3]", "bad_message"},
      {R"({"op": 5})", "bad_message"},
      {R"({"no_op": true})", "bad_message"},
      {R"({"op": "fly_to_the_moon"})", "unknown_op"},
  };
  for (const auto& [text, code] : cases) {
    client.send_text(text);
    const auto error = client.read_op("error");
    EXPECT_EQ(error["code"], code) << text;
    EXPECT_FALSE(error["message"].get<std::string>().empty());
  }
  client.send_binary(std::string("\x00\x01\x02", 3));
  EXPECT_EQ(client.read_op("error")["code"], "bad_message");
  client.send_text(R"({"op":"ping","id":7})");
  EXPECT_EQ(client.read_op("pong")["id"], 7);
  EXPECT_EQ(client.read_op("pose")["op"], "pose");  // still streaming
}

TEST_F(WebSocketStream, OversizedMessageClosesOnlyThatClient) {
  WsClient other(port());
  WsClient client(port());
  bool closed = false;
  try {
    client.send_text(std::string(200 * 1024, 'x'));
  } catch (const beast::system_error&) {
    closed = true;  // the server may close before the last bytes are sent: a reset mid-write
  }
  closed = closed || client.closed_by_server();
  EXPECT_TRUE(closed);
  EXPECT_EQ(other.read_op("pose")["op"], "pose");
}

TEST_F(WebSocketStream, UnsupportedSubprotocolIsRefused) {
  EXPECT_THROW(WsClient(port(), "strata.v999"), beast::system_error);
  // Ours among others: the server picks ours and says so.
  WsClient listing_ours(port(), "something.else, strata.v1");
  EXPECT_EQ(listing_ours.handshake_response()[http::field::sec_websocket_protocol], "strata.v1");
  EXPECT_EQ(listing_ours.read()["op"], "hello");
  // None at all (a plain client): v1, and no subprotocol named back that the client did not offer.
  WsClient plain(port(), "");
  EXPECT_EQ(plain.handshake_response().count(http::field::sec_websocket_protocol), 0u);
  EXPECT_EQ(plain.read()["op"], "hello");
}

TEST_F(WebSocketStream, UpgradeElsewhereIsRefused) {
  EXPECT_THROW(WsClient(port(), "strata.v1", "/api/v1/pose"), beast::system_error);
}

TEST_F(WebSocketStream, ManyClientsAllReceivePoses) {
  std::vector<std::unique_ptr<WsClient>> clients;
  for (int i = 0; i < 20; ++i)
    clients.push_back(std::make_unique<WsClient>(port()));
  for (auto& client : clients) {
    client->read_op("pose");
    const auto live = client->read_op("pose");
    EXPECT_TRUE(live["stamp"].is_number());
  }
}

}  // namespace
}  // namespace strata::testing

// Who may do what, and what a misbehaving client can and cannot do: the real server, real WebSocket and
// HTTP clients (proto/PROTOCOL.md "Who may do what", "Limits").
#include <gtest/gtest.h>

#include <thread>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

class Control : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new ServerProcess({"--scanner", "none", "--time-scale", "4"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static inline ServerProcess* server_ = nullptr;
};

TEST_F(Control, HelloTellsEachConnectionItsRole) {
  WsClient viewer(port());
  EXPECT_EQ(viewer.read()["role"], "viewer");
  auto by_subprotocol = WsClient::operator_client(port(), kTestOperatorToken);
  EXPECT_EQ(by_subprotocol->read()["role"], "operator");
  // The server answers with strata.v1 only: the token is never echoed.
  EXPECT_EQ(by_subprotocol->handshake_response()[http::field::sec_websocket_protocol], "strata.v1");
  WsClient by_header(port(), "strata.v1", "/ws", std::string("Bearer ") + kTestOperatorToken);
  EXPECT_EQ(by_header.read()["role"], "operator");
}

TEST_F(Control, AWrongTokenIsRefusedAtTheUpgrade) {
  EXPECT_THROW(WsClient(port(), "strata.v1, strata.token.not-the-right-token"), beast::system_error);
  EXPECT_THROW(WsClient(port(), "strata.v1", "/ws", "Bearer not-the-right-token"), beast::system_error);
  // The refusal is counted.
  const auto metrics = http_get(port(), "/metrics").body();
  EXPECT_EQ(metrics.find("strata_auth_failures_total 0\n"), std::string::npos) << metrics;
}

TEST_F(Control, ViewersCannotControlAndNothingChanges) {
  const auto goal_before = http_get(port(), "/api/v1/goal");
  WsClient viewer(port());
  viewer.read_op("hello");
  const char* commands[] = {R"({"op":"set_goal","x":1,"y":1,"id":1})", R"({"op":"cancel_goal","id":2})",
                            R"({"op":"teleop","v":0.3,"w":0,"id":3})",
                            R"({"op":"save_map","name":"x","id":4})",
                            R"({"op":"load_map","name":"x","id":5})"};
  for (const char* command : commands) {
    viewer.send_text(command);
    const auto error = viewer.read_op("error");
    EXPECT_EQ(error["code"], "unauthorized") << command;
    EXPECT_EQ(error["id"], nlohmann::json::parse(command)["id"]) << command;
    EXPECT_EQ(error["request"], nlohmann::json::parse(command)["op"]) << command;
  }
  const auto goal_after = http_get(port(), "/api/v1/goal");
  EXPECT_EQ(goal_after.result(), goal_before.result());
  EXPECT_EQ(goal_after.body(), goal_before.body());
}

TEST_F(Control, RestControlNeedsTheBearerToken) {
  auto refused = http_request(port(), http::verb::post, "/api/v1/goal", R"({"x":1,"y":1})");
  EXPECT_EQ(refused.result(), http::status::unauthorized);
  expect_schema("rest", "error", nlohmann::json::parse(refused.body()));
  auto wrong =
      http_request(port(), http::verb::post, "/api/v1/goal", R"({"x":1,"y":1})", "wrong-token-0000000");
  EXPECT_EQ(wrong.result(), http::status::unauthorized);
  // Anyone may list the saved maps; loading one needs the token.
  auto maps = http_request(port(), http::verb::get, "/api/v1/maps");
  EXPECT_EQ(maps.result(), http::status::ok);
  auto load = http_request(port(), http::verb::post, "/api/v1/maps/any.strata/load", "");
  EXPECT_EQ(load.result(), http::status::unauthorized);
  auto bad =
      http_request(port(), http::verb::post, "/api/v1/goal", R"({"x":"far","y":1})", kTestOperatorToken);
  EXPECT_EQ(bad.result(), http::status::bad_request);
  EXPECT_EQ(nlohmann::json::parse(bad.body())["error"]["code"], "bad_params");
}

TEST_F(Control, SubscribingFiltersTheStreams) {
  WsClient client(port());
  client.read_op("hello");
  client.send_text(R"({"op":"subscribe","streams":["status"],"id":"s"})");
  const auto ack = client.read_op("ack");
  EXPECT_EQ(ack["request"], "subscribe");
  EXPECT_EQ(ack["id"], "s");
  // Poses come at 25 Hz; the status at 1 Hz. Between two status messages no pose may arrive.
  int statuses = 0;
  while (statuses < 2) {
    const auto message = client.read();
    if (message["op"] == "status")
      ++statuses;
    else
      EXPECT_NE(message["op"], "pose");
  }
  client.send_text(R"({"op":"subscribe","streams":["pose","status"]})");
  client.read_op("pose");  // added back: the current pose comes at once
}

TEST_F(Control, FloodingIsRateLimitedAndTheConnectionStays) {
  WsClient client(port());
  client.read_op("hello");
  constexpr int kSent = 300;
  for (int i = 0; i < kSent; ++i)
    client.send_text(R"({"op":"ping","id":)" + std::to_string(i) + "}");
  int pongs = 0;
  int limited = 0;
  while (pongs + limited < kSent) {
    const auto message = client.read();
    if (message["op"] == "pong")
      ++pongs;
    else if (message["op"] == "error" && message["code"] == "rate_limited")
      ++limited;
  }
  EXPECT_GE(pongs, 80);  // the burst
  EXPECT_GT(limited, 0);
  // Still connected: once the bucket refills, pings are answered again.
  for (int attempt = 0; attempt < 100; ++attempt) {
    client.send_text(R"({"op":"ping","id":"again"})");
    nlohmann::json reply;
    do {
      reply = client.read();
    } while (reply["op"] != "pong" && reply["op"] != "error");
    if (reply["op"] == "pong")
      return;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ADD_FAILURE() << "no pong after the flood";
}

TEST_F(Control, AClientThatStopsReadingDoesNotHoldUpOthers) {
  const long before = server_->resident_kib();
  // Connected, never reads: the server's writes to it back up in the socket, then in its queue.
  std::vector<std::unique_ptr<WsClient>> stuck;
  for (int i = 0; i < 5; ++i)
    stuck.push_back(std::make_unique<WsClient>(port()));
  WsClient reader(port());
  double last_stamp = -1.0;
  for (int poses = 0; poses < 100;) {
    const auto message = reader.read();
    if (message["op"] != "pose")
      continue;
    EXPECT_GT(message["stamp"].get<double>(), last_stamp);
    last_stamp = message["stamp"];
    ++poses;
  }
  const long after = server_->resident_kib();
  // Poses and status coalesce: a stuck client holds one of each, not a backlog.
  EXPECT_LT(after - before, 64 * 1024) << "KiB before " << before << ", after " << after;
}

}  // namespace
}  // namespace strata::testing

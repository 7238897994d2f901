// Safe over a poor link and against hostile input (issue 59), against the real server: teleop commands
// that a link outage held back never move the robot when they arrive; JSON nested deeper than anything of
// ours is refused over REST and the WebSocket without harm, on a 1 MiB stack.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "integration/clients.hpp"
#include "integration/link_proxy.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

/// The true pose (the simulator's) from the next pose message.
nlohmann::json next_truth(WsClient& client) {
  for (int i = 0; i < 1000; ++i) {
    const auto message = client.read();
    if (message["op"] == "pose")
      return message["truth"];
  }
  throw std::runtime_error("no pose");
}

double moved(const nlohmann::json& from, const nlohmann::json& to) {
  return std::hypot(to["x"].get<double>() - from["x"].get<double>(),
                    to["y"].get<double>() - from["y"].get<double>()) +
         std::abs(to["yaw"].get<double>() - from["yaw"].get<double>());
}

/// Reads poses for `span` of wall time; returns the largest motion from `from` and when it first exceeded
/// 1 mm (or -1 ms: never).
std::pair<double, double> watch(WsClient& client, const nlohmann::json& from,
                                std::chrono::milliseconds span) {
  const auto start = Clock::now();
  double largest = 0.0;
  double first_motion_ms = -1.0;
  while (Clock::now() - start < span) {
    const double motion = moved(from, next_truth(client));
    largest = std::max(largest, motion);
    if (motion > 1e-3 && first_motion_ms < 0.0)
      first_motion_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }
  return {largest, first_motion_ms};
}

/// Reads poses until the true pose has not changed for 20 poses; returns it.
nlohmann::json wait_until_still(WsClient& client) {
  nlohmann::json previous = next_truth(client);
  int still = 0;
  for (int i = 0; i < 5000 && still < 20; ++i) {
    const auto truth = next_truth(client);
    still = moved(previous, truth) < 1e-4 ? still + 1 : 0;
    previous = truth;
  }
  if (still < 20)
    throw std::runtime_error("the robot did not stand still");
  return previous;
}

TEST(LinkSafety, TeleopCommandsHeldBackByAnOutageNeverMoveTheRobot) {
  ServerProcess server({"--scanner", "none"});
  LinkProxy link(server.port(), LinkConditions{.delay = 40ms});
  WsClient observer(server.port());  // beside the link: sees the robot as it is
  auto op = WsClient::operator_client(link.port(), kTestOperatorToken);
  TeleopStamper stamper(op->read_op("hello"));
  op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");  // ends the demo route; stops need no stamp
  op->read_op("ack");
  const auto standing = wait_until_still(observer);

  // The operator holds the stick through a 3 s outage and lets go of it just before the link returns, as
  // in the report: 20 commands a second, sent but held back, then delivered all at once.
  link.set_down(true);
  for (int i = 0; i < 60; ++i) {
    op->send_text(stamper.command(0.3, 0.6));
    std::this_thread::sleep_for(50ms);
  }
  std::this_thread::sleep_for(300ms);  // the stick let go 0.3 s before the link returns; nothing sent since
  link.set_down(false);
  const auto [largest, first_motion_ms] = watch(observer, standing, 1500ms);
  std::printf("stale burst: robot moved %.4f (m + rad) after the link returned, first motion at %.0f ms\n",
              largest, first_motion_ms);
  EXPECT_LT(largest, 1e-3) << "a command held back by the outage moved the robot";
  const auto refusal = op->read_op("error");
  EXPECT_EQ(refusal["code"], "stale_command") << refusal.dump();
  const auto metrics = http_get(server.port(), "/metrics").body();
  EXPECT_NE(metrics.find("strata_ws_stale_teleop_total 60"), std::string::npos) << "all 60 refused";

  // The link is good again: fresh commands drive, as before the outage.
  for (int i = 0; i < 20; ++i) {
    op->send_text(stamper.command(0.3, 0.6));
    std::this_thread::sleep_for(50ms);
  }
  double driven = 0.0;
  for (int i = 0; i < 200 && driven < 0.01; ++i)  // poses queued before the commands come first
    driven = moved(standing, next_truth(observer));
  EXPECT_GT(driven, 0.01) << "fresh teleop over the link did not move the robot";
  EXPECT_EQ(server.stop(), 0);
}

TEST(LinkSafety, AMovingTeleopNeedsItsStampAndAnOlderOneIsRefused) {
  ServerProcess server({"--scanner", "none"});
  auto op = WsClient::operator_client(server.port(), kTestOperatorToken);
  const auto hello = op->read_op("hello");
  EXPECT_EQ(hello["protocol_minor"], 1);
  TeleopStamper stamper(hello);
  op->send_text(R"({"op":"teleop","v":0.3,"w":0,"id":"unstamped"})");
  EXPECT_EQ(op->read_op("error")["code"], "bad_params");
  const std::string first = stamper.command(0.3, 0.0);
  const std::string second = stamper.command(0.3, 0.0);
  op->send_text(second);
  op->send_text(first);  // overtaken: out of order
  const auto refusal = op->read_op("error");
  EXPECT_EQ(refusal["code"], "stale_command");
  EXPECT_NE(refusal["message"].get<std::string>().find("out of order"), std::string::npos) << refusal.dump();
  EXPECT_EQ(server.stop(), 0);
}

/// `depth` nested arrays around a number: "[[[...1...]]]".
std::string nested_arrays(std::size_t depth) {
  return std::string(depth, '[') + "1" + std::string(depth, ']');
}

TEST(HostileInput, DeeplyNestedJsonIsRefusedOnAOneMebibyteStack) {
  ServerProcess server({"--scanner", "none"}, ProcessLimits{.stack = 1024 * 1024});
  // REST: an operator's goal of 70,000 nested arrays (it crashed the server as it re-serialised the body).
  const auto goal = http_request(server.port(), http::verb::post, "/api/v1/goal",
                                 R"({"x":)" + nested_arrays(70000) + "}", kTestOperatorToken);
  EXPECT_EQ(goal.result_int(), 400);
  const auto body = nlohmann::json::parse(goal.body());
  EXPECT_EQ(body["error"]["code"], "bad_json");
  EXPECT_NE(body["error"]["message"].get<std::string>().find("deeper than 64"), std::string::npos)
      << goal.body();
  // WebSocket, no token at all: a subscribe whose item is 32,700 arrays deep (it was echoed back).
  WsClient viewer(server.port());
  viewer.read_op("hello");
  viewer.send_text(R"({"op":"subscribe","streams":[)" + nested_arrays(32700) + "]}");
  EXPECT_EQ(viewer.read_op("error")["code"], "bad_json");
  // Within the bound, an item that is not a stream name is named briefly, never echoed whole.
  viewer.send_text(R"({"op":"subscribe","streams":[)" + nested_arrays(60) + "]}");
  const auto refusal = viewer.read_op("error");
  EXPECT_EQ(refusal["code"], "bad_params");
  EXPECT_LT(refusal["message"].get<std::string>().size(), 200U);
  // Nothing else changed: the server answers, and no goal was set.
  EXPECT_EQ(http_get(server.port(), "/healthz").result_int(), 200);
  EXPECT_EQ(nlohmann::json::parse(http_get(server.port(), "/api/v1/goal").body())["phase"], "none");
  EXPECT_EQ(server.stop(), 0);
}

}  // namespace
}  // namespace strata::testing

// Safe over a poor link and against hostile input (issue 59), against the real server: teleop commands
// that a link outage held back never move the robot when they arrive; a slow link gets a recent pose, not
// a backlog, and a late joiner's pose does not wait for its map; a silent client is dropped and counted;
// JSON nested deeper than anything of ours is refused over REST and the WebSocket without harm, on a 1 MiB
// stack.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

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
nlohmann::json wait_until_observed_still(WsClient& client) {
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
  const auto standing = wait_until_observed_still(observer);

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

/// The wall-clock time now, s: a pose's `server_time` is on it.
double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// Waits (reading `client`) until the map has at least `tiles` tiles; returns how many it has.
int wait_for_tiles(WsClient& client, int tiles) {
  for (int i = 0; i < 600; ++i) {
    const auto status = client.read_op("status", 2000);
    if (status["map"]["tiles"].get<int>() >= tiles)
      return status["map"]["tiles"].get<int>();
  }
  throw std::runtime_error("the map did not grow");
}

TEST(LinkSafety, ALateJoinersPoseIsNotHeldBackUntilItsMapHasStreamed) {
  ServerProcess server({"--time-scale", "10"});
  WsClient observer(server.port());
  const int tiles = wait_for_tiles(observer, 25);
  // 0.2 Mbit/s: the map's tiles (most of a kilobyte each) take seconds to cross.
  LinkProxy link(server.port(), LinkConditions{.delay = 40ms, .bytes_per_second = 25000});
  WsClient late(link.port());
  int tiles_received = 0;
  int poses_between_tiles = 0;  // poses that came after the first tile and before the last
  int poses_since_a_tile = 0;
  while (tiles_received < tiles) {
    const auto frame = late.read_frame(10s);
    if (frame.binary && !frame.data.empty() && frame.data[0] == 1) {
      poses_between_tiles += tiles_received > 0 ? poses_since_a_tile : 0;
      poses_since_a_tile = 0;
      ++tiles_received;
    } else if (!frame.binary && nlohmann::json::parse(frame.data)["op"] == "pose") {
      ++poses_since_a_tile;
    }
  }
  std::printf("late joiner at 0.2 Mbit/s: %d poses came among its %d tiles\n", poses_between_tiles, tiles);
  // Before, the pose waited behind every tile: at most the one queued with them came between.
  EXPECT_GE(poses_between_tiles, 5) << "the pose waited until the map had streamed";
  EXPECT_EQ(server.stop(), 0);
}

TEST(LinkSafety, ASlowLinkGetsTheNewestPoseNotABacklog) {
  ServerProcess server({"--time-scale", "5"});
  WsClient observer(server.port());
  wait_for_tiles(observer, 10);
  LinkProxy link(server.port(), LinkConditions{.delay = 40ms, .bytes_per_second = 25000});  // 0.2 Mbit/s
  WsClient viewer(link.port());
  // The map grows all the while (the simulator at 5x): more than the link carries.
  std::vector<double> ages;
  const auto until = Clock::now() + 12s;
  while (Clock::now() < until) {
    const auto frame = viewer.read_frame(10s);
    if (frame.binary)
      continue;
    const auto message = nlohmann::json::parse(frame.data);
    if (message["op"] == "pose")
      ages.push_back(wall_seconds() - message["server_time"].get<double>());
  }
  ASSERT_GT(ages.size(), 20u);
  // The last third: long after the joining snapshot, when a backlog would have built up.
  std::vector<double> late_ages(ages.end() - static_cast<std::ptrdiff_t>(ages.size() / 3), ages.end());
  std::ranges::sort(late_ages);
  const double median = late_ages[late_ages.size() / 2];
  std::printf("0.2 Mbit/s: %zu poses in 12 s, the last third's median age %.2f s, oldest %.2f s\n",
              ages.size(), median, late_ages.back());
  // The link's own queue is about 0.4 s at this rate; the server's socket may hold a quarter second more.
  EXPECT_LT(median, 1.5) << "poses queue up in front of the slow client";
  // What it could see from outside: the client's queue and its pose's age.
  const auto metrics = http_get(server.port(), "/metrics").body();
  EXPECT_NE(metrics.find("strata_ws_client_pose_age_seconds{client="), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("strata_ws_client_socket_bytes{client="), std::string::npos);
  EXPECT_EQ(server.stop(), 0);
}

TEST(LinkSafety, ASilentClientIsDroppedAndCounted) {
  ServerProcess server({"--scanner", "none", "--client-timeout", "2"});
  WsClient silent(server.port());
  silent.read_op("hello");  // and never reads again: it answers no ping
  EXPECT_NE(http_get(server.port(), "/metrics").body().find("strata_ws_clients 1\n"), std::string::npos);
  std::this_thread::sleep_for(4s);
  const auto metrics = http_get(server.port(), "/metrics").body();
  EXPECT_NE(metrics.find("strata_ws_slow_clients_dropped_total 1\n"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("strata_ws_clients 0\n"), std::string::npos) << metrics;
  EXPECT_EQ(server.stop(), 0);
}

TEST(HostileInput, ClientsFetchingTheSameExportCostOneEncoding) {
  // The sensor goes quiet after 10 simulated seconds: the map stops changing, as when the robot stands.
  ServerProcess server({"--time-scale", "5", "--sim-sensor-outage", "10,100000"});
  WsClient observer(server.port());
  int version = -1;
  for (int i = 0; i < 120; ++i) {
    const int now = observer.read_op("status", 2000)["map"]["version"].get<int>();
    if (now > 0 && now == version)
      break;
    version = now;
  }
  ASSERT_GT(version, 0) << "no map";
  std::vector<HttpResponse> downloads(4);  // as many as the server works on at once
  std::vector<std::thread> clients;
  for (auto& download : downloads)
    clients.emplace_back([&] { download = http_get(server.port(), "/api/v1/map?format=ply"); });
  for (auto& client : clients)
    client.join();
  int made = 0;
  for (const auto& download : downloads) {
    ASSERT_EQ(download.result(), http::status::ok) << download.body();
    EXPECT_EQ(download.body(), downloads.front().body());
    EXPECT_EQ(download["X-Strata-Version"], std::to_string(version));
    made += download["X-Strata-Export"] == "made" ? 1 : 0;
  }
  EXPECT_EQ(made, 1) << "four clients asked for the same export at once: it is made once";
  // Another format is another export; the first is not lost for it.
  EXPECT_EQ(http_get(server.port(), "/api/v1/map?format=strata")["X-Strata-Export"], "made");
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);
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

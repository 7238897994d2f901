// A user's scripted mission against the real server and simulator, over the real protocol: watch the map
// arrive, drive to a goal, fail on an unreachable one, cancel, teleoperate, save, load and download the map
// (issue #7 item 7). The yard world keeps it short; the simulator runs faster than real time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>
#include <vector>

#include "core/mls/mls_tile.hpp"
#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

/// Reads until a `goal` message with goal `id` reaches one of `phases`; fails after `timeout` of wall time.
nlohmann::json wait_for_goal(WsClient& client, std::uint64_t id, std::initializer_list<std::string> phases,
                             std::chrono::seconds timeout = std::chrono::seconds(180)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  nlohmann::json last;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto message = client.read(std::chrono::seconds(30));
    if (message["op"] != "goal" || message["id"] != id)
      continue;
    last = message;
    for (const auto& phase : phases) {
      if (message["phase"] == phase)
        return message;
    }
  }
  throw std::runtime_error("goal " + std::to_string(id) + " did not reach the phase; last: " + last.dump());
}

/// Reads until the status reports a map of at least `version` (scans inserted): goals need known ground.
void wait_for_map(WsClient& client, std::uint64_t version) {
  for (int i = 0; i < 20000; ++i) {
    const auto message = client.read(std::chrono::seconds(60));
    if (message["op"] == "status" && message["map"]["version"].get<std::uint64_t>() >= version)
      return;
  }
  throw std::runtime_error("no map of version " + std::to_string(version));
}

/// Reads poses until the true position has not moved by more than 1 mm over 20 poses; returns that pose.
nlohmann::json wait_until_still(WsClient& client, int limit = 5000) {
  std::vector<nlohmann::json> recent;
  for (int i = 0; i < limit; ++i) {
    const auto message = client.read();
    if (message["op"] != "pose")
      continue;
    recent.push_back(message["truth"]);
    if (recent.size() < 20)
      continue;
    const auto& first = recent[recent.size() - 20];
    const auto& last = recent.back();
    if (std::hypot(last["x"].get<double>() - first["x"].get<double>(),
                   last["y"].get<double>() - first["y"].get<double>()) < 1e-3)
      return last;
  }
  throw std::runtime_error("the robot did not stand still");
}

class Mission : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    maps_dir_ = std::filesystem::temp_directory_path() / ("strata-mission-" + std::to_string(::getpid()));
    std::filesystem::remove_all(maps_dir_);
    server_ = new ServerProcess(
        {"--world", "yard", "--scanner", "tilting", "--time-scale", "2", "--maps-dir", maps_dir_.string()});
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
    std::filesystem::remove_all(maps_dir_);
  }
  static std::uint16_t port() { return server_->port(); }
  static inline ServerProcess* server_ = nullptr;
  static inline std::filesystem::path maps_dir_;
};

std::uint8_t frame_kind(const std::string& frame) {
  return frame.empty() ? 0 : static_cast<std::uint8_t>(frame[0]);
}

TEST_F(Mission, TheMapArrivesAsTilesAndAnOccupancyImage) {
  WsClient client(port());
  bool tile = false;
  bool occupancy = false;
  for (int i = 0; i < 20000 && !(tile && occupancy); ++i) {
    client.read(std::chrono::seconds(60));
    for (const auto& frame : client.binary_frames()) {
      tile = tile || frame_kind(frame) == 1;
      occupancy = occupancy || frame_kind(frame) == 2;
    }
  }
  ASSERT_TRUE(tile && occupancy);
  for (const auto& frame : client.binary_frames()) {
    ASSERT_GE(frame.size(), 24u);
    std::uint16_t header_bytes = 0;
    std::memcpy(&header_bytes, frame.data() + 2, 2);
    EXPECT_LE(header_bytes, frame.size());
    if (frame_kind(frame) == 1 && frame.size() > header_bytes) {
      EXPECT_EQ(frame.substr(header_bytes, 5), "DRACO");
    }
    if (frame_kind(frame) == 2) {
      EXPECT_EQ(frame.substr(header_bytes + 1, 3), "PNG");
    }
  }
  // A late joiner gets the map at once.
  WsClient late(port());
  late.read_op("hello");
  for (int i = 0; i < 50 && late.binary_frames().empty(); ++i)
    late.read();
  EXPECT_FALSE(late.binary_frames().empty());
  // And REST serves the same tiles with ETags.
  const auto index = nlohmann::json::parse(http_get(port(), "/api/v1/tiles").body());
  expect_schema("rest", "tiles", index);
  ASSERT_FALSE(index["tiles"].empty());
  const auto& first = index["tiles"][0];
  const std::string target =
      "/api/v1/tiles/" + std::to_string(first["x"].get<int>()) + "/" + std::to_string(first["y"].get<int>());
  const auto tile_response = http_get(port(), target);
  EXPECT_EQ(tile_response.result(), http::status::ok);
  EXPECT_FALSE(tile_response[http::field::etag].empty());
}

TEST_F(Mission, DrivesToGoalsOnScannedGroundAndRefusesAnUnreachableOne) {
  auto op = WsClient::operator_client(port(), kTestOperatorToken);
  op->read_op("hello");
  // Stop the demo route where the robot starts, and wait for its first scan: the goal is on known ground.
  op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");
  op->read_op("ack");
  wait_for_map(*op, 1);
  op->send_text(R"({"op":"set_goal","x":-6,"y":-5.5,"id":"g1"})");
  const auto ack = op->read_op("ack");
  EXPECT_EQ(ack["id"], "g1");
  const auto goal = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body());
  expect_schema("rest", "goal", goal);
  const std::uint64_t id = goal["id"];
  const auto reached = wait_for_goal(*op, id, {"reached", "failed", "cancelled"});
  ASSERT_EQ(reached["phase"], "reached") << reached.dump();
  const auto pose = op->read_op("pose");
  EXPECT_LT(std::hypot(pose["x"].get<double>() + 6.0, pose["y"].get<double>() + 5.5), 0.6) << pose.dump();
  expect_schema("rest", "path", nlohmann::json::parse(http_get(port(), "/api/v1/path").body()));

  // Further out, over ground the tilting laser saw only in rings: the gaps between them are inferred.
  op->send_text(R"({"op":"set_goal","x":-6.5,"y":-1.5})");
  op->read_op("ack");
  const auto further = wait_for_goal(*op, id + 1, {"reached", "failed", "cancelled"});
  ASSERT_EQ(further["phase"], "reached") << further.dump();
  const auto there = op->read_op("pose");
  EXPECT_LT(std::hypot(there["x"].get<double>() + 6.5, there["y"].get<double>() + 1.5), 0.6) << there.dump();

  // The west fence: seen, and no place to drive.
  op->send_text(R"({"op":"set_goal","x":-9.9,"y":-6})");
  op->read_op("ack");
  const auto fence = wait_for_goal(*op, id + 2, {"reached", "failed", "cancelled"});
  EXPECT_EQ(fence["phase"], "failed");
  EXPECT_EQ(fence["reason"], "goal_not_drivable");
  EXPECT_EQ(fence["message"].get<std::string>().rfind(
                "the goal is not a drivable place with room for the robot", 0),
            0U)
      << fence.dump();
  // REST says the same.
  const auto rest_goal = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body());
  EXPECT_EQ(rest_goal["reason"], fence["reason"]);
  EXPECT_EQ(rest_goal["message"], fence["message"]);
}

TEST_F(Mission, CancelStopsTheRobot) {
  auto op = WsClient::operator_client(port(), kTestOperatorToken);
  op->read_op("hello");
  op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");
  op->read_op("ack");
  wait_for_map(*op, 1);
  // Two metres: at time scale 2 it drives for about two seconds, time to cancel on the way.
  op->send_text(R"({"op":"set_goal","x":-5,"y":-5.5})");
  op->read_op("ack");
  const std::uint64_t id = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body())["id"];
  const auto driving = wait_for_goal(*op, id, {"driving", "failed", "reached"});
  ASSERT_EQ(driving["phase"], "driving") << driving.dump();
  op->send_text(R"({"op":"cancel_goal","id":"c"})");
  EXPECT_EQ(op->read_op("ack")["id"], "c");
  EXPECT_EQ(wait_for_goal(*op, id, {"cancelled"})["phase"], "cancelled");
  wait_until_still(*op);
}

TEST_F(Mission, TeleopMovesTheRobotAndStopsWhenTheCommandsStop) {
  auto op = WsClient::operator_client(port(), kTestOperatorToken);
  TeleopStamper stamper(op->read_op("hello"));
  // A stop command ends the demo route; then the robot stands until told. It does not move while it takes
  // a stop-and-go scan, so wait for the first one to finish.
  op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");
  op->read_op("ack");
  wait_for_map(*op, 1);
  const auto start = wait_until_still(*op);
  for (int i = 0; i < 20; ++i) {
    op->send_text(stamper.command(0.3, 0.4));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // No more commands: it stops by itself (the commands expire after 0.5 s).
  const auto stopped = wait_until_still(*op);
  EXPECT_GT(std::hypot(stopped["x"].get<double>() - start["x"].get<double>(),
                       stopped["y"].get<double>() - start["y"].get<double>()) +
                std::abs(stopped["yaw"].get<double>() - start["yaw"].get<double>()),
            0.01)
      << "teleop did not move the robot";
}

TEST_F(Mission, ClosingTheConnectionStopsATeleoperatedRobot) {
  WsClient observer(port());
  wait_for_map(observer, 1);  // the robot stands still at the start (its first scan, the gyro's bias)
  const auto before = nlohmann::json::parse(http_get(port(), "/api/v1/pose").body())["truth"];
  {
    auto op = WsClient::operator_client(port(), kTestOperatorToken);
    TeleopStamper stamper(op->read_op("hello"));
    // Forward, the way the demo route starts: backwards from the start the robot has no room (under ctest
    // each test has a fresh server, so it starts there).
    for (int i = 0; i < 20; ++i) {  // 1 s: up to speed
      // An id asks for an ack: proof each command was taken.
      op->send_text(stamper.command(0.2, 0.0, 1));
      op->read_op("ack");
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }  // closed while the last command is still valid
  const double closed_at =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  // Where the robot was when the connection closed (the last pose the server made before), and where it
  // came to rest. The lease alone would have driven it 0.5 s more: 0.2 m at 0.2 m/s and 2x real time, and
  // then it slows down (0.03 m).
  std::optional<nlohmann::json> at_close;
  std::vector<nlohmann::json> recent;
  for (int i = 0; i < 5000; ++i) {
    const auto message = observer.read();
    if (message["op"] != "pose")
      continue;
    if (message["server_time"].get<double>() <= closed_at)
      at_close = message["truth"];
    recent.push_back(message["truth"]);
    if (recent.size() >= 20 && at_close && message["server_time"].get<double>() > closed_at &&
        std::hypot(recent.back()["x"].get<double>() - recent[recent.size() - 20]["x"].get<double>(),
                   recent.back()["y"].get<double>() - recent[recent.size() - 20]["y"].get<double>()) < 1e-3)
      break;
  }
  ASSERT_TRUE(at_close) << "no pose from before the close";
  const double driven = std::hypot((*at_close)["x"].get<double>() - before["x"].get<double>(),
                                   (*at_close)["y"].get<double>() - before["y"].get<double>());
  EXPECT_GT(driven, 0.02) << "the teleop commands did not drive the robot";
  const double after_close = std::hypot(recent.back()["x"].get<double>() - (*at_close)["x"].get<double>(),
                                        recent.back()["y"].get<double>() - (*at_close)["y"].get<double>());
  std::printf("teleoperated robot: %.3f m driven, %.3f m after its operator's connection closed\n", driven,
              after_close);
  EXPECT_LT(after_close, 0.12) << "the close did not stop the robot: the lease did";
}

/// Reads status messages until the server counts `clients` WebSocket clients.
void wait_for_clients(WsClient& client, std::size_t clients) {
  wait_for_status(client, [clients](const nlohmann::json& status) { return status["clients"] == clients; });
}

TEST_F(Mission, ClosingTheOperatorConnectionCancelsItsGoalAndStopsTheRobot) {
  WsClient observer(port());
  std::uint64_t id = 0;
  {
    auto op = WsClient::operator_client(port(), kTestOperatorToken);
    op->read_op("hello");
    op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");
    op->read_op("ack");
    wait_for_map(*op, 1);
    // Of two goals the robot reached before, the farther one: it drives for a few seconds.
    const auto pose = nlohmann::json::parse(http_get(port(), "/api/v1/pose").body());
    const bool near_south = std::hypot(pose["x"].get<double>() + 6.0, pose["y"].get<double>() + 5.5) < 2.0;
    op->send_text(near_south ? R"({"op":"set_goal","x":-6.5,"y":-1.5})"
                             : R"({"op":"set_goal","x":-6,"y":-5.5})");
    op->read_op("ack");
    id = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body())["id"];
    const auto driving = wait_for_goal(*op, id, {"driving", "failed", "reached"});
    ASSERT_EQ(driving["phase"], "driving") << driving.dump();
  }  // the operator's connection closes mid-goal
  const auto cancelled = wait_for_goal(observer, id, {"cancelled", "reached", "failed"});
  EXPECT_EQ(cancelled["phase"], "cancelled") << cancelled.dump();
  EXPECT_EQ(cancelled["reason"], "operator_disconnected") << cancelled.dump();
  const auto goal = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body());
  expect_schema("rest", "goal", goal);
  EXPECT_EQ(goal["id"], id);
  EXPECT_EQ(goal["phase"], "cancelled");
  EXPECT_EQ(goal["reason"], "operator_disconnected");
  // The robot stops and stays stopped: two more seconds of poses without a millimetre of motion.
  const auto still = wait_until_still(observer);
  for (int poses = 0; poses < 50;) {
    const auto message = observer.read();
    if (message["op"] != "pose")
      continue;
    ++poses;
    EXPECT_LT(std::hypot(message["truth"]["x"].get<double>() - still["x"].get<double>(),
                         message["truth"]["y"].get<double>() - still["y"].get<double>()),
              1e-3);
  }

  // A goal set over REST has no connection: an operator connection that closes does not cancel it, even
  // one that had set the goal it replaced.
  std::uint64_t rest_id = 0;
  {
    auto op = WsClient::operator_client(port(), kTestOperatorToken);
    op->read_op("hello");
    op->send_text(R"({"op":"set_goal","x":-6.5,"y":-1.5})");
    op->read_op("ack");
    const auto replaced =
        http_request(port(), http::verb::post, "/api/v1/goal", R"({"x":-6,"y":-5.5})", kTestOperatorToken);
    ASSERT_EQ(replaced.result(), http::status::accepted) << replaced.body();
    rest_id = nlohmann::json::parse(replaced.body())["id"];
  }
  wait_for_clients(observer, 1);  // the server has let the operator's connection go
  const auto rest_goal = nlohmann::json::parse(http_get(port(), "/api/v1/goal").body());
  EXPECT_EQ(rest_goal["id"], rest_id);
  EXPECT_NE(rest_goal["phase"], "cancelled") << rest_goal.dump();
  http_request(port(), http::verb::delete_, "/api/v1/goal", {}, kTestOperatorToken);  // for the next test
}

TEST_F(Mission, SavesLoadsAndDownloadsTheMap) {
  auto op = WsClient::operator_client(port(), kTestOperatorToken);
  op->read_op("hello");
  wait_for_map(*op, 1);
  op->send_text(R"({"op":"save_map","name":"yard.strata","id":"s"})");
  const auto saved = op->read_op("ack");
  EXPECT_EQ(saved["id"], "s");
  EXPECT_TRUE(std::filesystem::exists(maps_dir_ / "yard.strata"));

  const auto list = http_request(port(), http::verb::get, "/api/v1/maps", {}, kTestOperatorToken);
  ASSERT_EQ(list.result(), http::status::ok);
  const auto maps = nlohmann::json::parse(list.body());
  expect_schema("rest", "maps", maps);
  ASSERT_EQ(maps["maps"].size(), 1u);
  EXPECT_EQ(maps["maps"][0]["name"], "yard.strata");

  op->send_text(R"({"op":"load_map","name":"missing.strata","id":"l1"})");
  const auto missing = op->read_op("error");
  EXPECT_EQ(missing["code"], "not_found");
  EXPECT_EQ(missing["id"], "l1");

  // A corrupt file is refused and the map is kept.
  {
    std::ofstream corrupt(maps_dir_ / "corrupt.strata", std::ios::binary);
    corrupt << "definitely not a map";
  }
  op->send_text(R"({"op":"load_map","name":"corrupt.strata","id":"l2"})");
  EXPECT_EQ(op->read_op("error")["code"], "corrupt_file");

  op->send_text(R"({"op":"load_map","name":"yard.strata","id":"l3"})");
  EXPECT_EQ(op->read_op("ack")["id"], "l3");

  for (const char* format : {"strata", "ply", "pgm", "yaml"}) {
    const auto download = http_get(port(), std::string("/api/v1/map?format=") + format);
    EXPECT_EQ(download.result(), http::status::ok) << format;
    EXPECT_GT(download.body().size(), 16u) << format;
  }
  EXPECT_EQ(http_get(port(), "/api/v1/map?format=ply").body().substr(0, 3), "ply");
  EXPECT_EQ(http_get(port(), "/api/v1/map?format=pgm").body().substr(0, 2), "P5");

  // The ROS map is the whole level, and a YAML's image is fetched by the version it names, however the
  // map moves on meanwhile.
  const auto tiles = nlohmann::json::parse(http_get(port(), "/api/v1/tiles").body())["tiles"];
  ASSERT_FALSE(tiles.empty());
  int min_x = tiles[0]["x"], max_x = min_x, min_y = tiles[0]["y"], max_y = min_y;
  for (const auto& tile : tiles) {
    min_x = std::min(min_x, tile["x"].get<int>());
    max_x = std::max(max_x, tile["x"].get<int>());
    min_y = std::min(min_y, tile["y"].get<int>());
    max_y = std::max(max_y, tile["y"].get<int>());
  }
  const auto yaml = http_get(port(), "/api/v1/map?format=yaml");
  ASSERT_EQ(yaml.result(), http::status::ok);
  const std::string version(yaml["X-Strata-Version"]);
  ASSERT_FALSE(version.empty());
  EXPECT_NE(yaml.body().find("format=pgm&version=" + version), std::string::npos) << yaml.body();
  const auto pgm = http_get(port(), "/api/v1/map?format=pgm&version=" + version);
  ASSERT_EQ(pgm.result(), http::status::ok) << pgm.body();
  int width = 0;
  int height = 0;
  ASSERT_EQ(std::sscanf(pgm.body().c_str(), "P5\n# strata drivable map\n%d %d", &width, &height), 2);
  EXPECT_GE(width, (max_x - min_x + 1) * kMlsTileSize) << "every tile of the map, not a window";
  EXPECT_GE(height, (max_y - min_y + 1) * kMlsTileSize);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(http_get(port(), "/api/v1/map?format=pgm&version=" + version).body(), pgm.body());
  EXPECT_EQ(http_get(port(), "/api/v1/map?format=pgm&version=abc").result(), http::status::bad_request);
}

// Issue 24: the goal the scripting guide sends with curl (docs/scripting.md) is driven to in the default
// demo (the campus): an example that fails "off_map" teaches a new user nothing.
TEST(DocumentedExamples, TheScriptingGuidesGoalIsDrivenToInTheDefaultDemo) {
  std::ifstream guide(std::filesystem::path(STRATA_DEPLOY_DIR) / ".." / "docs" / "scripting.md");
  ASSERT_TRUE(guide) << "docs/scripting.md not found";
  std::string body;
  for (std::string line; std::getline(guide, line);) {
    if (line.find("/api/v1/goal") == std::string::npos || line.find("-d '") == std::string::npos)
      continue;
    const std::size_t start = line.find("-d '") + 4;
    body = line.substr(start, line.find('\'', start) - start);
    break;
  }
  ASSERT_FALSE(body.empty()) << "no curl goal example in docs/scripting.md";
  ServerProcess server({"--time-scale", "4"});
  WsClient watcher(server.port());
  wait_for_status(watcher, [](const nlohmann::json& s) { return s["map"]["cells"].get<int>() > 1000; });
  const auto sent = http_request(server.port(), http::verb::post, "/api/v1/goal", body, kTestOperatorToken);
  ASSERT_EQ(sent.result_int() / 100, 2u) << sent.body();
  const auto id = nlohmann::json::parse(sent.body())["id"].get<std::uint64_t>();
  const auto goal = wait_for_goal(watcher, id, {"driving", "reached", "failed"});
  EXPECT_NE(goal["phase"], "failed") << body << ": " << goal.dump();
}

}  // namespace
}  // namespace strata::testing

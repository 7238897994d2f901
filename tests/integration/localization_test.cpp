// The demo's second lap lands on its first (issue #20): the real server with the simulated robot in the
// yard, faster than real time, watched over REST as a user would. The pose graph closes the loop when
// the robot comes round again; from then on the estimate stays on the truth, between scans too: over the
// platform and down its far ramp the height follows the ground (PoseExtrapolator), where the last scan's
// tilt carried on would climb 0.4 m above it. (That the map is rebuilt
// from the moved keyframes is tested in the mapping worker's unit tests: no client surface reports it yet.)
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "integration/clients.hpp"
#include "integration/protocol_schemas.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

nlohmann::json get_json(std::uint16_t port, const std::string& target) {
  const auto response = http_get(port, target);
  EXPECT_EQ(response.result_int(), 200) << target;
  return nlohmann::json::parse(response.body());
}

// The simulation runs against the wall clock. The sanitizer build registers a scan 4-5 times slower, and at
// time scale 20 beside another test it drops half the scans (28 of 61): the first lap then has half its
// keyframes, a 13 m stretch of odometry-only heading, and lands 0.37 m off (CI, 2026-11-26). At 8 it keeps
// up as the release build does at 20 (4 of 48 dropped, 0.04 m).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr const char* kTimeScale = "8";
#else
constexpr const char* kTimeScale = "20";
#endif

TEST(Localization, TheSecondLapLandsOnTheFirst) {
  ServerProcess server({"--world", "yard", "--scanner", "tilting", "--time-scale", kTimeScale});
  // The yard's demo lap is about 200 simulated seconds; past 2.5 laps, then a few more checks.
  constexpr double kSecondLapDone = 500.0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(10);
  double worst_after_loop = 0.0;
  int checked = 0;
  nlohmann::json status;
  while (checked < 20) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the simulation did not get through two laps";
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const nlohmann::json pose = get_json(server.port(), "/api/v1/pose");
    if (pose["stamp"].get<double>() < kSecondLapDone)
      continue;
    status = get_json(server.port(), "/api/v1/status");
    ASSERT_GE(status["pose_graph"]["loops"].get<int>(), 3) << status.dump();
    const nlohmann::json& truth = pose["truth"];
    const double xy = std::hypot(pose["x"].get<double>() - truth["x"].get<double>(),
                                 pose["y"].get<double>() - truth["y"].get<double>());
    const double z = std::abs(pose["z"].get<double>() - truth["z"].get<double>());
    worst_after_loop = std::max(worst_after_loop, xy);
    EXPECT_LT(xy, 0.3) << "at t=" << pose["stamp"] << ": " << pose.dump();
    EXPECT_LT(z, 0.15) << "at t=" << pose["stamp"] << ": " << pose.dump();
    ++checked;
  }
  RecordProperty("worst_xy_error_after_loop_m", std::to_string(worst_after_loop));
  EXPECT_EQ(status["registration"]["scans"].get<int>(),
            status["registration"]["full"].get<int>() + status["registration"]["partial"].get<int>() +
                status["registration"]["kept_odometry"].get<int>() + 1)
      << "every scan but the first is counted once: " << status.dump();
}

// Map reuse (issue #22): a map one run saved is what the next run localizes in. The first server maps the
// start of the yard lap and saves it; the second starts with it (--map, --mode localize) and another seed:
// its estimate is on the truth from its first scans, the map it serves does not grow, an operator's pose
// estimate a metre off is searched around and the robot found where it is, and a goal on ground the first
// run drove is reached without any further mapping. The second robot is stopped before the pose estimate:
// the search takes seconds of wall time (10 s in an ASan build), and a robot driving on along the demo
// route meanwhile would leave the mapped part of the lap after a distance that depends on the machine.
TEST(Localization, ARestartLocalizesInTheSavedMapAndGoalsWorkAtOnce) {
  const std::filesystem::path maps = private_temp_path("strata-localize-maps", "");
  std::filesystem::remove_all(maps);
  double goal_x = 0.0;
  double goal_y = 0.0;
  {
    ServerProcess mapping(
        {"--world", "yard", "--scanner", "tilting", "--time-scale", kTimeScale, "--maps-dir", maps.string()});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    bool goal_taken = false;
    constexpr double kMappedUntil = 120.0;  // simulated seconds of the lap the saved map covers
    while (true) {
      ASSERT_LT(std::chrono::steady_clock::now(), deadline)
          << "the first run did not get " << kMappedUntil << " s in";
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      const nlohmann::json pose = get_json(mapping.port(), "/api/v1/pose");
      if (!goal_taken && pose["stamp"].get<double>() >= 50.0) {
        goal_x = pose["truth"]["x"].get<double>();
        goal_y = pose["truth"]["y"].get<double>();
        goal_taken = true;
      }
      if (pose["stamp"].get<double>() >= kMappedUntil)
        break;
    }
    const auto saved = http_request(mapping.port(), http::verb::post, "/api/v1/maps",
                                    R"({"name":"yard.smls"})", kTestOperatorToken);
    ASSERT_EQ(saved.result_int(), 201) << saved.body();
    // While mapping there is no saved map to search: a pose estimate is refused with the reason.
    const auto refused = http_request(mapping.port(), http::verb::post, "/api/v1/pose/estimate",
                                      R"({"x":0,"y":0,"yaw":0})", kTestOperatorToken);
    EXPECT_EQ(refused.result_int(), 400) << refused.body();
    EXPECT_NE(refused.body().find("localizes in no saved map"), std::string::npos) << refused.body();
    // The map as the web app's Download gives it, for another robot (issue 63).
    const auto downloaded = http_get(mapping.port(), "/api/v1/map?format=strata");
    ASSERT_EQ(downloaded.result_int(), 200);
    std::ofstream(maps / "downloaded.smls", std::ios::binary) << downloaded.body();
  }
  {
    // The downloaded file is the file a save writes: a robot localizes in it (it had the map alone, and
    // `--mode localize` refused it: "has no localization data").
    ServerProcess from_download({"--world", "yard", "--scanner", "none", "--maps-dir", maps.string(), "--map",
                                 "downloaded.smls", "--mode", "localize"});
    const nlohmann::json status = get_json(from_download.port(), "/api/v1/status");
    EXPECT_EQ(status["map"]["mode"], "localize") << status.dump();
    EXPECT_GT(status["map"]["patches"].get<int>(), 0) << status.dump();
  }

  ServerProcess localizing({"--world", "yard", "--scanner", "tilting", "--time-scale", kTimeScale, "--seed",
                            "2", "--maps-dir", maps.string(), "--map", "yard.smls", "--mode", "localize"});
  const nlohmann::json before = get_json(localizing.port(), "/api/v1/status");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  // Checked while it drives on, until 10 checks or until it has driven half the mapped lap on a slow machine.
  int checked = 0;
  double stamp = 0.0;
  while (checked < 10 && !(checked >= 3 && stamp >= 60.0)) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "no registered scans in the saved map";
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const nlohmann::json status = get_json(localizing.port(), "/api/v1/status");
    if (status["registration"]["full"].get<int>() + status["registration"]["partial"].get<int>() < 2)
      continue;
    const nlohmann::json pose = get_json(localizing.port(), "/api/v1/pose");
    const nlohmann::json& truth = pose["truth"];
    stamp = pose["stamp"].get<double>();
    const double xy = std::hypot(pose["x"].get<double>() - truth["x"].get<double>(),
                                 pose["y"].get<double>() - truth["y"].get<double>());
    EXPECT_LT(xy, 0.2) << pose.dump();
    EXPECT_EQ(status["map"]["patches"], before["map"]["patches"]) << "the saved map is not changed";
    ++checked;
  }
  {
    // The operator stops the demo route (on a real robot too, one tells it where it is before it drives on).
    auto op = WsClient::operator_client(localizing.port(), kTestOperatorToken);
    op->read_op("hello");
    op->send_text(R"({"op":"teleop","v":0,"w":0,"id":"stop"})");
    op->read_op("ack");
  }
  // An operator's pose estimate 1 m and 17 degrees off: the robot is found where it is, and stays there.
  const nlohmann::json now = get_json(localizing.port(), "/api/v1/pose");
  const nlohmann::json estimate{{"x", now["truth"]["x"].get<double>() + 0.8},
                                {"y", now["truth"]["y"].get<double>() - 0.6},
                                {"yaw", now["truth"]["yaw"].get<double>() + 0.3}};
  const auto hinted = http_request(localizing.port(), http::verb::post, "/api/v1/pose/estimate",
                                   estimate.dump(), kTestOperatorToken);
  ASSERT_EQ(hinted.result_int(), 202) << hinted.body();
  nlohmann::json relocalization;
  while (relocalization.is_null()) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the pose estimate was never searched around";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    relocalization = get_json(localizing.port(), "/api/v1/status")["relocalization"];
  }
  EXPECT_TRUE(relocalization["found"].get<bool>()) << relocalization.dump();
  const nlohmann::json placed = get_json(localizing.port(), "/api/v1/pose");
  EXPECT_LT(std::hypot(placed["x"].get<double>() - placed["truth"]["x"].get<double>(),
                       placed["y"].get<double>() - placed["truth"]["y"].get<double>()),
            0.2)
      << placed.dump();

  const auto goal = http_request(localizing.port(), http::verb::post, "/api/v1/goal",
                                 nlohmann::json{{"x", goal_x}, {"y", goal_y}}.dump(), kTestOperatorToken);
  ASSERT_EQ(goal.result_int(), 202) << goal.body();
  std::string phase;
  while (phase != "reached" && phase != "failed") {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the goal was not reached: " << phase;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    phase = get_json(localizing.port(), "/api/v1/goal")["phase"].get<std::string>();
  }
  EXPECT_EQ(phase, "reached") << get_json(localizing.port(), "/api/v1/goal").dump();
  std::filesystem::remove_all(maps);
}

// The IMU calibration is kept between runs (issue #20): a robot's scan path learns its IMU's mounting error
// only as it turns, and tilts its way by it until then. The first run keeps the pose graph's estimate once
// a loop closure confirms it; the next run of the same robot (seed) starts from it, another robot's does
// not; an operator can make the robot forget it.
TEST(Localization, TheImuCalibrationIsKeptForTheNextRunOfTheSameRobot) {
  const std::filesystem::path file = private_temp_path("strata-imu-calibration", ".json");
  std::filesystem::remove(file);
  const std::vector<std::string> args{"--world",      "yard",     "--scanner",         "tilting",
                                      "--time-scale", kTimeScale, "--imu-calibration", file.string()};
  ProtocolSchemas schemas;
  nlohmann::json kept;
  {
    ServerProcess first(args);
    const nlohmann::json at_start = get_json(first.port(), "/api/v1/imu-calibration");
    EXPECT_EQ(at_start["kept"], "none") << at_start.dump();
    EXPECT_EQ(at_start["imu"], "simulated IMU, seed 1") << at_start.dump();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (kept.is_null() || kept["kept"] != "saved") {
      ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "no loop closure kept the calibration";
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      kept = get_json(first.port(), "/api/v1/status")["pose_graph"]["imu_calibration"];
    }
    EXPECT_GE(kept["loops"].get<int>(), 1) << kept.dump();
    EXPECT_TRUE(std::filesystem::exists(file));
    const nlohmann::json answer = get_json(first.port(), "/api/v1/imu-calibration");
    EXPECT_EQ(schemas.violations("rest", "imu_calibration", answer), "") << answer.dump();
  }
  // What the next run starts from is the file as the first left it: more loops may have closed (and
  // saved) after the requests above.
  nlohmann::json saved;
  {
    std::ifstream in(file);
    saved = nlohmann::json::parse(in);
  }
  EXPECT_EQ(saved["imu"], "simulated IMU, seed 1") << saved.dump();
  // Another robot (another seed: another IMU) does not start from it.
  {
    std::vector<std::string> other = args;
    other.insert(other.end(), {"--seed", "2"});
    ServerProcess second(other);
    const nlohmann::json status = get_json(second.port(), "/api/v1/status");
    EXPECT_EQ(status["pose_graph"]["imu_calibration"]["kept"], "none") << status.dump();
    EXPECT_EQ(status["pose_graph"]["gravity_mounting_roll_deg"].get<double>(), 0.0) << status.dump();
  }
  // The same robot starts from it: the scan path levels with it before any loop closure.
  ServerProcess again(args);
  const nlohmann::json status = get_json(again.port(), "/api/v1/status");
  EXPECT_EQ(schemas.violations("rest", "status", status), "") << status.dump();
  const nlohmann::json& graph = status["pose_graph"];
  EXPECT_EQ(graph["loops"].get<int>(), 0) << status.dump();
  EXPECT_EQ(graph["imu_calibration"]["kept"], "loaded") << status.dump();
  const double roll = saved["mounting_roll_deg"].get<double>();
  const double pitch = saved["mounting_pitch_deg"].get<double>();
  EXPECT_NEAR(graph["imu_calibration"]["roll_deg"].get<double>(), roll, 1e-9);
  EXPECT_NEAR(graph["imu_calibration"]["pitch_deg"].get<double>(), pitch, 1e-9);
  EXPECT_EQ(graph["imu_calibration"]["loops"], saved["loops"]);
  EXPECT_NEAR(graph["gravity_mounting_roll_deg"].get<double>(), roll, 1e-9);
  EXPECT_NEAR(graph["gravity_mounting_pitch_deg"].get<double>(), pitch, 1e-9);

  // Forgetting it is the operator's.
  const auto refused = http_request(again.port(), http::verb::delete_, "/api/v1/imu-calibration", "");
  EXPECT_EQ(refused.result_int(), 401) << refused.body();
  EXPECT_TRUE(std::filesystem::exists(file));
  const auto cleared =
      http_request(again.port(), http::verb::delete_, "/api/v1/imu-calibration", "", kTestOperatorToken);
  ASSERT_EQ(cleared.result_int(), 200) << cleared.body();
  const nlohmann::json forgotten = nlohmann::json::parse(cleared.body());
  EXPECT_EQ(schemas.violations("rest", "imu_calibration", forgotten), "") << forgotten.dump();
  EXPECT_EQ(forgotten["kept"], "none") << forgotten.dump();
  EXPECT_FALSE(std::filesystem::exists(file));
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace strata::testing

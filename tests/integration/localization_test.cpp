// The demo's second lap lands on its first (issue #20): the real server with the simulated robot in the
// yard, faster than real time, watched over REST as a user would. The pose graph closes the loop when
// the robot comes round again; from then on the estimate stays on the truth, between scans too: over the
// platform and down its far ramp the height follows the ground (PoseExtrapolator), where the last scan's
// tilt carried on would climb 0.4 m above it. (That the map is rebuilt
// from the moved keyframes is tested in the mapping worker's unit tests: no client surface reports it yet.)
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "integration/clients.hpp"
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

}  // namespace
}  // namespace strata::testing

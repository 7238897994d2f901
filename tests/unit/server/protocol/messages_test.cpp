#include "server/protocol/messages.hpp"

#include <gtest/gtest.h>

#include "server/protocol/protocol.hpp"

namespace strata::protocol {
namespace {

TEST(Messages, PoseCarriesTheEstimateAndTheTruth) {
  RobotSample sample;
  sample.stamp = 3.25;
  sample.odometry.position = {1.0, -2.0, 0.1};
  sample.odometry.roll = 0.01;
  sample.odometry.pitch = -0.02;
  sample.odometry.yaw = 1.5;
  sample.truth = Pose3{};
  sample.truth->position = {1.1, -2.1, 0.1};
  RobotSnapshot robot{sample, sample.odometry, false};
  robot.estimate.position.x() = 1.0;
  const auto message = nlohmann::json::parse(pose_message(robot));
  EXPECT_EQ(message["op"], "pose");
  EXPECT_DOUBLE_EQ(message["stamp"], 3.25);
  EXPECT_DOUBLE_EQ(message["x"], 1.0);
  EXPECT_DOUBLE_EQ(message["y"], -2.0);
  EXPECT_DOUBLE_EQ(message["z"], 0.1);
  EXPECT_DOUBLE_EQ(message["roll"], 0.01);
  EXPECT_DOUBLE_EQ(message["pitch"], -0.02);
  EXPECT_DOUBLE_EQ(message["yaw"], 1.5);
  EXPECT_DOUBLE_EQ(message["truth"]["x"], 1.1);
  EXPECT_DOUBLE_EQ(message["odometry"]["y"], -2.0);
  EXPECT_EQ(message["source"], "odometry");
  EXPECT_EQ(message["mode"], "driving");
}

TEST(Messages, PoseHasNoTruthWhenNothingKnowsIt) {
  RobotSample sample;  // a lidar's: no simulator, no reference poses
  sample.odometry.position = {1.0, 2.0, 0.0};
  const RobotSnapshot robot{sample, sample.odometry, false};
  const auto message = nlohmann::json::parse(pose_message(robot));
  EXPECT_FALSE(message.contains("truth"));
  EXPECT_DOUBLE_EQ(message["odometry"]["y"], 2.0);
}

// Issue 24: "doing: driving" while the robot stood. A base that knows its velocity (the simulator) and
// reports none stands; a base that does not know it (a replay, a lidar alone) is not said to stand.
TEST(Messages, PoseSaysStandingOnlyWhereTheBaseKnowsItStands) {
  RobotSample sample;
  sample.velocity_known = true;
  const auto mode = [&] {
    return nlohmann::json::parse(pose_message({sample, sample.odometry, true}))["mode"];
  };
  EXPECT_EQ(mode(), "standing");
  sample.velocity.w = 0.2;
  EXPECT_EQ(mode(), "driving");
  sample.scanning = true;
  EXPECT_EQ(mode(), "scanning");
  sample.blocked_by = "step";
  EXPECT_EQ(mode(), "blocked");
  RobotSample replay;  // velocity unknown, zero
  EXPECT_EQ(nlohmann::json::parse(pose_message({replay, replay.odometry, true}))["mode"], "driving");
}

TEST(Messages, HelloNamesTheProtocolAndTheServerClock) {
  const auto hello = nlohmann::json::parse(hello_message("operator", 1234.5));
  EXPECT_EQ(hello["op"], "hello");
  EXPECT_EQ(hello["protocol"], kSubprotocol);
  EXPECT_EQ(hello["protocol_version"], kVersion);
  EXPECT_EQ(hello["protocol_minor"], kMinorVersion);
  EXPECT_EQ(hello["role"], "operator");
  EXPECT_EQ(hello["clock_ms"], 1234.5);
  EXPECT_EQ(nlohmann::json::parse(pong_message(7, 99.0))["clock_ms"], 99.0);
}

TEST(Messages, ErrorsCarryCodes) {
  const auto error = nlohmann::json::parse(error_message(ErrorCode::kUnknownOp, "what"));
  EXPECT_EQ(error["op"], "error");
  EXPECT_EQ(error["code"], "unknown_op");
  EXPECT_EQ(error["message"], "what");
  const auto rest = nlohmann::json::parse(rest_error(ErrorCode::kNotFound, "gone"));
  EXPECT_EQ(rest["error"]["code"], "not_found");
}

TEST(Messages, StatusSaysHowFarThePoseCanBeTrusted) {
  RegistrationStatus registration;  // before the first scan
  auto message = nlohmann::json::parse(status_message(registration, {}));
  EXPECT_EQ(message["op"], "status");
  EXPECT_EQ(message["localization"]["state"], "degraded");
  EXPECT_EQ(message["localization"]["reason"], "no scan yet: position from odometry only");
  registration.localization = {LocalizationState::kLost, "no scan matched for 10 scans"};
  message = nlohmann::json::parse(status_message(registration, {}));
  EXPECT_EQ(message["localization"],
            (nlohmann::json{{"state", "lost"}, {"reason", "no scan matched for 10 scans"}}));
}

TEST(Messages, SimWorldListsEveryShape) {
  sim::WorldDescription d;
  d.name = "w";
  d.boxes.push_back({"b", {0, 1, 2}, {1, 2, 3}, 0.5});
  d.ramps.push_back({"r", {4, 4}, 2, 1, 0.0, 0.0, 0.0, 0.2});
  d.cylinders.push_back({{1, 1}, 0.1, 0, 2});
  d.spheres.push_back({{0, 0, 3}, 1});
  d.terrain = sim::HeightField({-5, -5}, 1.0, 11, 11, std::vector<double>(121, 0.0));
  const auto message = nlohmann::json::parse(sim_world_message(sim::World(d)));
  EXPECT_EQ(message["op"], "sim_world");
  EXPECT_EQ(message["name"], "w");
  ASSERT_EQ(message["boxes"].size(), 1u);
  EXPECT_EQ(message["boxes"][0]["size"], nlohmann::json::array({1.0, 2.0, 3.0}));
  EXPECT_DOUBLE_EQ(message["boxes"][0]["yaw"], 0.5);
  EXPECT_EQ(message["ramps"][0]["height_end"], 0.2);
  EXPECT_EQ(message["cylinders"].size(), 1u);
  EXPECT_EQ(message["spheres"].size(), 1u);
  EXPECT_EQ(message["terrain"]["nx"], 11);
  EXPECT_EQ(message["terrain"]["heights"].size(), 121u);
  EXPECT_EQ(message["bounds"]["min"][0], -5.0);
}

}  // namespace
}  // namespace strata::protocol

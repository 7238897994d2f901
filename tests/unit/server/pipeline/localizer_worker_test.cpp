#include "server/pipeline/localizer_worker.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "tests/support/sim_saved_map.hpp"

namespace strata::pipeline {
namespace {

/// What the status's relocalization says as the scans come: each new message once, and the latest answer.
struct RelocalizationAnswers {
  std::vector<std::string> messages;
  std::optional<RegistrationStatus::Relocalization> latest;

  void take(const RobotState& state) {
    latest = state.registration().relocalization;
    if (latest && (messages.empty() || messages.back() != latest->message))
      messages.push_back(latest->message);
  }
  [[nodiscard]] bool found() const { return latest && latest->found; }
};

// A robot that believes it starts 5.7 m from where it does, in a saved map of the yard: its scans cannot
// register (the jump limit is 1 m), it is lost after ten of them, and then it is searched for over the whole
// map (at the first lost scan and every 5th after, until found); from there its scans register where it is.
TEST(LocalizerWorker, ARobotLostInASavedMapIsFoundAgain) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  auto saved = std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 21));
  sim::Simulator run(world, {.seed = 2});
  Eigen::Isometry3d wrong = Eigen::Isometry3d::Identity();
  wrong.translation() = Eigen::Vector3d(4.0, -4.0, 0.0);
  const Eigen::Isometry3d believed =
      wrong * run.sample().truth->to_isometry() * run.sample().odometry.to_isometry().inverse();
  RobotState state;
  LocalizerWorker worker(state, GraphLocalizerOptions{}, believed);
  std::optional<double> last_error;
  worker.set_registered_scan_sink([&](PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                                      const std::optional<KeyframeAnchor>&) {
    const Eigen::Isometry3d truth = scan.event.truth->to_isometry() * scan.event.sensor_to_base;
    last_error = (map_from_sensor.translation() - truth.translation()).norm();
  });
  EXPECT_FALSE(worker.set_pose_estimate({.x = 0.0, .y = 0.0, .yaw = 0.0, .z = std::nullopt}).ok)
      << "no map to search yet";
  worker.localize_in(saved);
  worker.start();
  bool found = false;
  std::size_t scans = 0;
  while (scans < 40 && !(found && last_error)) {
    run.step(0.01);
    for (ScanEvent& scan : run.take_scans()) {
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      ++scans;
      const RegistrationStatus status = state.registration();
      if (status.relocalization && status.relocalization->found && !found) {
        found = true;
        EXPECT_EQ(status.localization.state, LocalizationState::kLost) << "searched only once lost";
        last_error.reset();  // from the next scan on
      }
    }
  }
  worker.stop();
  ASSERT_TRUE(found) << "never found in " << scans
                     << " scans: " << state.registration().relocalization->message;
  ASSERT_TRUE(last_error) << "no scan registered after it was found";
  EXPECT_LT(*last_error, 0.2);
}

// Lost in the campus's hallway, the whole-map search fits places along it as well; they are followed as
// the robot drives on, as an operator's estimate's are (before, each lost search began anew). Any place
// taken is the right one.
TEST(LocalizerWorker, ALostRobotsPlacesAreFollowedAsItDrivesOn) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("campus"));
  auto saved = std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 40));
  sim::Simulator run(world, {.seed = 2});
  Eigen::Isometry3d wrong = Eigen::Isometry3d::Identity();
  wrong.translation() = Eigen::Vector3d(0.0, 3.0, 0.0);
  const Eigen::Isometry3d believed =
      wrong * run.sample().truth->to_isometry() * run.sample().odometry.to_isometry().inverse();
  RobotState state;
  LocalizerWorker worker(state, GraphLocalizerOptions{}, believed);
  worker.localize_in(saved);
  worker.start();
  RelocalizationAnswers answers;
  std::size_t scans = 0;
  while (scans < 16 && !answers.found()) {
    run.step(0.01);
    state.publish(run.sample());
    for (ScanEvent& scan : run.take_scans()) {
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      ++scans;
      answers.take(state);
    }
  }
  worker.stop();
  const std::vector<std::string>& said = answers.messages;
  ASSERT_GE(said.size(), 2U) << "searched once lost, then followed";
  EXPECT_TRUE(said.front().starts_with("lost: ")) << said.front();
  EXPECT_NE(said.front().find("looked for at these"), std::string::npos) << said.front();
  EXPECT_FALSE(said[1].starts_with("lost: ")) << "the next scan follows the places: " << said[1];
  if (answers.found()) {
    const Pose3 estimate = state.snapshot()->estimate;
    const Pose3 truth = *run.sample().truth;
    EXPECT_LT((estimate.position.head<2>() - truth.position.head<2>()).norm(), 0.2)
        << answers.latest->message;
  }
}

/// A second run (seed 2) of a world, its worker started where the robot truly is and localizing in a map
/// saved from the first run's first `map_scans` scans.
struct RunInSavedMap {
  RunInSavedMap(const std::string& world_name, std::size_t map_scans)
      : world(std::make_shared<const sim::World>(sim::builtin_world(world_name))),
        run(world, {.seed = 2}),
        worker(state, GraphLocalizerOptions{},
               run.sample().truth->to_isometry() * run.sample().odometry.to_isometry().inverse()) {
    worker.localize_in(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, map_scans)));
    worker.start();
  }
  std::shared_ptr<const sim::World> world;
  sim::Simulator run;
  RobotState state;
  LocalizerWorker worker;
};

/// The robot's estimate now within 0.2 m of where it truly is.
void expect_estimate_on_truth(const RobotState& state, const sim::Simulator& run) {
  const Pose3 estimate = state.snapshot()->estimate;
  const Pose3 truth = *run.sample().truth;
  EXPECT_LT((estimate.position.head<2>() - truth.position.head<2>()).norm(), 0.2)
      << "estimate " << estimate.position.transpose() << ", truth " << truth.position.transpose();
}

// A stop-and-go scanner standing still takes no next scan: an operator's pose estimate is searched at once
// with the latest scan. Here the robot drove on 8 m after it (its scans not handed over, its odometry
// published as the driver does); the estimate, 0.6 m and 11 degrees from where it is now, is carried back
// by that odometry to where the scan was taken: found there, the estimate now is on the truth. Without the
// carrying back the search looks 8 m from the scan's place and is refused (two places fit as well).
TEST(LocalizerWorker, APoseEstimateIsSearchedWithTheLatestScanWithoutWaitingForAnother) {
  RunInSavedMap in_map("yard", 21);
  sim::Simulator& run = in_map.run;
  RobotState& state = in_map.state;
  LocalizerWorker& worker = in_map.worker;
  std::size_t scans = 0;
  Eigen::Vector2d last_scan_at = Eigen::Vector2d::Zero();
  while (scans < 3) {
    run.step(0.01);
    state.publish(run.sample());
    for (ScanEvent& scan : run.take_scans()) {
      last_scan_at = scan.truth->position.head<2>();
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      ++scans;
    }
  }
  while ((run.sample().truth->position.head<2>() - last_scan_at).norm() < 8.0) {
    run.step(0.01);
    state.publish(run.sample());
    static_cast<void>(run.take_scans());  // taken, never handed over
  }
  const Pose3 truth = *run.sample().truth;
  ASSERT_TRUE(worker
                  .set_pose_estimate({.x = truth.position.x() + 0.5,
                                      .y = truth.position.y() - 0.3,
                                      .yaw = truth.yaw + 0.2,
                                      .z = std::nullopt})
                  .ok);
  // The search runs on the worker's thread: wait for its answer (no scan comes meanwhile; a sanitized build
  // takes seconds for it).
  std::optional<RegistrationStatus::Relocalization> answer;
  for (int waited = 0; waited < 6000 && !answer; ++waited) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    answer = state.registration().relocalization;
  }
  worker.stop();
  ASSERT_TRUE(answer) << "the estimate was not searched without a new scan";
  EXPECT_TRUE(answer->found) << answer->message;
  const Pose3 estimate = state.snapshot()->estimate;
  EXPECT_LT((estimate.position.head<2>() - truth.position.head<2>()).norm(), 0.2)
      << "estimate " << estimate.position.transpose() << ", truth " << truth.position.transpose();
}

// In the campus's hallway one scan fits a metre along it as well: a pose estimate there (1 m off, 14 m
// before the hallway's end) is refused with the places that fit, and the robot is looked for at them as it
// drives on; the scans near the end tell them apart, and the robot is placed where it is.
TEST(LocalizerWorker, APoseEstimateThatFitsSeveralPlacesIsDecidedAsTheRobotDrivesOn) {
  RunInSavedMap in_map("campus", 40);
  sim::Simulator& run = in_map.run;
  RobotState& state = in_map.state;
  LocalizerWorker& worker = in_map.worker;
  std::size_t scans = 0;
  bool estimated = false;
  RelocalizationAnswers answers;
  while (scans < 30 && !answers.found()) {
    run.step(0.01);
    state.publish(run.sample());
    for (ScanEvent& scan : run.take_scans()) {
      const Pose3 truth = *scan.truth;
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      ++scans;
      answers.take(state);
      if (!estimated && truth.position.x() > 40.0) {  // along the hallway, the robot driving east
        estimated = true;
        ASSERT_TRUE(worker
                        .set_pose_estimate({.x = truth.position.x() + 1.0,
                                            .y = truth.position.y(),
                                            .yaw = truth.yaw,
                                            .z = std::nullopt})
                        .ok);
      }
    }
  }
  worker.stop();
  ASSERT_TRUE(answers.latest) << "never searched";
  const std::vector<std::string>& said = answers.messages;
  ASSERT_GE(said.size(), 2U);
  EXPECT_NE(said.front().find("two places fit as well"), std::string::npos) << said.front();
  EXPECT_NE(said.front().find("looked for at these"), std::string::npos) << said.front();
  ASSERT_TRUE(answers.found()) << answers.latest->message;
  expect_estimate_on_truth(state, run);
}

// A pose estimate searched with a scan that sees two walls the map lacks (a parked truck, a new fence) is
// refused, none of its places fitting well enough; the best of them is where the robot is looked for as
// it drives on, and the next scans, the walls gone, place it there.
TEST(LocalizerWorker, APoseEstimateThatFitsNowhereWellEnoughIsLookedForAtItsBestPlace) {
  RunInSavedMap in_map("yard", 14);
  sim::Simulator& run = in_map.run;
  RobotState& state = in_map.state;
  LocalizerWorker& worker = in_map.worker;
  std::size_t scans = 0;
  bool estimated = false;
  RelocalizationAnswers answers;
  while (scans < 14 && !answers.found()) {
    run.step(0.01);
    state.publish(run.sample());
    for (ScanEvent& scan : run.take_scans()) {
      const Pose3 truth = *scan.truth;
      const bool changed = ++scans == 6;
      if (changed) {  // the walls, 3.5 m ahead and to the left of the base
        const Eigen::Isometry3d base_to_sensor = scan.sensor_to_base.inverse();
        for (double a = -5.0; a <= 5.0; a += 0.05)
          for (double z = 0.4; z <= 2.4; z += 0.05) {
            scan.points.push_back((base_to_sensor * Eigen::Vector3d(3.5, a, z)).cast<float>());
            scan.points.push_back((base_to_sensor * Eigen::Vector3d(a, 3.5, z)).cast<float>());
          }
      }
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      answers.take(state);
      if (changed) {
        estimated = true;
        ASSERT_TRUE(
            worker.set_pose_estimate({.x = truth.position.x(), .y = truth.position.y(), .yaw = truth.yaw})
                .ok);
        for (int waited = 0; waited < 6000 && answers.messages.empty(); ++waited) {
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
          answers.take(state);
        }
      }
    }
  }
  worker.stop();
  ASSERT_TRUE(estimated);
  const std::vector<std::string>& said = answers.messages;
  ASSERT_GE(said.size(), 2U) << (said.empty() ? "never searched" : said.front());
  EXPECT_NE(said.front().find("no place fits"), std::string::npos) << said.front();
  EXPECT_NE(said.front().find("looked for at this place"), std::string::npos) << said.front();
  ASSERT_TRUE(answers.found()) << answers.latest->message;
  expect_estimate_on_truth(state, run);
}

}  // namespace
}  // namespace strata::pipeline

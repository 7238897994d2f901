#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <tuple>
#include <vector>

#include "server/pipeline/localizer_worker.hpp"
#include "tests/support/campus_scans.hpp"

namespace strata::pipeline {
namespace {

// The localizer hands each registered scan on with its sensor's corrected map-frame pose: the mapping
// worker's input. Scans go in one at a time (each waits for the previous to come out), so none is
// replaced while waiting; the wait is for an event, with a generous limit only against a hang.
TEST(LocalizerWorkerSink, HandsOnRegisteredScansWithTheirSensorPose) {
  const std::vector<ScanEvent>& scans = testing::campus_scans();
  ASSERT_GE(scans.size(), 2U);
  // The robot is told where it starts, as serve does: the map frame is the world's.
  const Eigen::Isometry3d map_from_odom =
      scans.front().truth->to_isometry() * scans.front().odometry.to_isometry().inverse();
  RobotState state;
  LocalizerWorker localizer(state, GraphLocalizerOptions{}, map_from_odom);

  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<std::tuple<PreprocessedScan, Eigen::Isometry3d, std::optional<KeyframeAnchor>>> received;
  localizer.set_registered_scan_sink([&](PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                                         const std::optional<KeyframeAnchor>& anchor) {
    std::lock_guard lock(mutex);
    received.emplace_back(std::move(scan), map_from_sensor, anchor);
    arrived.notify_all();
  });
  localizer.start();

  for (std::size_t i = 0; i < 2; ++i) {
    localizer.submit(scans[i]);
    std::unique_lock lock(mutex);
    ASSERT_TRUE(arrived.wait_for(lock, std::chrono::seconds(120), [&] { return received.size() == i + 1; }))
        << "scan " << i << " was not handed on";
  }
  localizer.stop();
  ASSERT_EQ(received.size(), 2U);  // the first, with nothing to register against, and a registered one
  for (std::size_t i = 0; i < received.size(); ++i) {
    const auto& [scan, map_from_sensor, anchor] = received[i];
    // Full resolution, preprocessed once (step 1) for the mapping worker too; the raw points released.
    EXPECT_EQ(scan.points.size(), points_in_base(scans[i]).size());
    EXPECT_FALSE(scan.points.empty());
    EXPECT_TRUE(scan.event.points.empty());
    const Eigen::Isometry3d truth = scan.event.truth->to_isometry() * scan.event.sensor_to_base;
    EXPECT_LT((map_from_sensor.translation() - truth.translation()).norm(), 0.3);
    // The keyframe the scan came after, for a map rebuild to move it with: the first scan is one itself,
    // at the pose it is mapped with.
    ASSERT_TRUE(anchor.has_value()) << "scan " << i;
    ASSERT_NE(anchor->keyframe, nullptr);
    EXPECT_LE(anchor->keyframe->stamp, scan.event.stamp);
    if (anchor->keyframe->stamp == scan.event.stamp) {
      EXPECT_TRUE(anchor->pose.isApprox(map_from_sensor * scan.event.sensor_to_base.inverse(), 1e-9));
    }
  }
  EXPECT_EQ(std::get<2>(received[0])->keyframe->stamp, scans[0].stamp);
}

// A registration that diverges (issue #10): one scan arrives with an odometry guess 3 m and 60 degrees off
// (a wheel slipping on a ramp, a robot carried away). Whatever ICP makes of it, fault control must reject
// it: the scan is not handed on to the map, the map <- odometry correction stays as it was (the odometry
// guess is kept), and the next scan, with its odometry right again, registers and is mapped.
TEST(LocalizerWorkerSink, ADivergedRegistrationIsRejectedAndNotMappedAndTheNextScanRecovers) {
  const std::vector<ScanEvent>& scans = testing::campus_scans();
  ASSERT_GE(scans.size(), 3U);
  const Eigen::Isometry3d map_from_odom =
      scans.front().truth->to_isometry() * scans.front().odometry.to_isometry().inverse();
  RobotState state;
  LocalizerWorker localizer(state, GraphLocalizerOptions{}, map_from_odom);
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<ScanEvent> mapped;
  localizer.set_registered_scan_sink([&](PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                                         const std::optional<KeyframeAnchor>&) {
    const Eigen::Isometry3d truth = scan.event.truth->to_isometry() * scan.event.sensor_to_base;
    EXPECT_LT((map_from_sensor.translation() - truth.translation()).norm(), 0.3)
        << "at t=" << scan.event.stamp;
    std::lock_guard lock(mutex);
    mapped.push_back(std::move(scan.event));
    arrived.notify_all();
  });
  // The estimate for one fixed odometry pose: it moves only when the correction does.
  RobotSample fixed;
  fixed.odometry = scans.front().odometry;
  state.publish(fixed);
  EXPECT_EQ(state.registration().localization.state, LocalizationState::kDegraded) << "no scan yet";
  localizer.start();
  // One scan at a time; flush() returns once it is registered and handed on or rejected.
  const auto register_one = [&](ScanEvent scan) {
    localizer.submit(std::move(scan));
    ASSERT_TRUE(localizer.flush());
  };

  register_one(scans[0]);
  const Pose3 estimate_before = state.snapshot()->estimate;
  EXPECT_EQ(state.registration().localization.state, LocalizationState::kOk);
  EXPECT_EQ(state.registration().localization.reason, "first scan: the map starts here");

  ScanEvent diverged = scans[1];
  const double yaw = diverged.odometry.yaw;
  diverged.odometry.position += Eigen::Vector3d(3.0 * std::cos(yaw + 1.0), 3.0 * std::sin(yaw + 1.0), 0.0);
  diverged.odometry.yaw = std::remainder(yaw + std::numbers::pi / 3.0, 2.0 * std::numbers::pi);
  register_one(diverged);
  const RegistrationStatus after_diverged = state.registration();
  ASSERT_TRUE(after_diverged.last.has_value());
  EXPECT_EQ(after_diverged.last->verdict, "rejected") << after_diverged.last->message;
  EXPECT_EQ(after_diverged.last->correction, "none");
  EXPECT_EQ(after_diverged.rejected, 1U);
  EXPECT_EQ(after_diverged.kept_odometry, 1U) << "what the panel calls kept odometry";
  // One unmatched scan is no reason to worry yet, but the status says what happened.
  EXPECT_EQ(after_diverged.localization.state, LocalizationState::kOk);
  EXPECT_EQ(after_diverged.localization.reason.rfind("the last scan kept odometry: ", 0), 0U)
      << after_diverged.localization.reason;
  {
    std::lock_guard lock(mutex);
    EXPECT_EQ(mapped.size(), 1U) << "the rejected scan was handed on to the map";
  }
  const Pose3 estimate_after = state.snapshot()->estimate;
  EXPECT_LT((estimate_after.position - estimate_before.position).norm(), 1e-9) << "the correction moved";
  EXPECT_NEAR(estimate_after.yaw, estimate_before.yaw, 1e-9);

  register_one(scans[2]);
  localizer.stop();
  const RegistrationStatus after_good = state.registration();
  EXPECT_EQ(after_good.last->verdict, "accepted") << after_good.last->message;
  EXPECT_NE(after_good.last->correction, "none");
  EXPECT_EQ(after_good.rejected, 1U);
  EXPECT_EQ(after_good.kept_odometry, 1U);
  EXPECT_EQ(after_good.full + after_good.partial, 1U) << "the good scan was used, whole or partly";
  EXPECT_EQ(after_good.localization.state, LocalizationState::kOk) << after_good.localization.reason;
  EXPECT_EQ(after_good.localization.reason.find("kept odometry"), std::string::npos)
      << after_good.localization.reason;
  std::lock_guard lock(mutex);
  ASSERT_EQ(mapped.size(), 2U);
  EXPECT_EQ(mapped[0].stamp, scans[0].stamp);
  EXPECT_EQ(mapped[1].stamp, scans[2].stamp);  // the good one after the diverged one
}

}  // namespace
}  // namespace strata::pipeline

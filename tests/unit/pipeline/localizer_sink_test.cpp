#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <vector>

#include "server/pipeline/localizer_worker.hpp"
#include "tests/unit/pipeline/campus_scans.hpp"

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
  LocalizerWorker localizer(state, LocalizerOptions{}, map_from_odom);

  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<std::pair<ScanEvent, Eigen::Isometry3d>> received;
  localizer.set_registered_scan_sink([&](ScanEvent scan, const Eigen::Isometry3d& map_from_sensor) {
    std::lock_guard lock(mutex);
    received.emplace_back(std::move(scan), map_from_sensor);
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
  for (const auto& [scan, map_from_sensor] : received) {
    EXPECT_FALSE(scan.points.empty()) << "full resolution, as the driver took it";
    const Eigen::Isometry3d truth = scan.truth->to_isometry() * scan.sensor_to_base;
    EXPECT_LT((map_from_sensor.translation() - truth.translation()).norm(), 0.3);
  }
}

}  // namespace
}  // namespace strata::pipeline

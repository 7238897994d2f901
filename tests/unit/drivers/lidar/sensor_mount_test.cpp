// The lidar's mount on the base when nobody gave it (issue 23 item 3): estimated from the ground under the
// sensor in its first scan, the simulated lidar's known height found again, the real HDL-32E's over its
// road; a given mount kept as given.
#include "drivers/sensor_mount.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "drivers/lidar/pcap_scan_source.hpp"
#include "drivers/sim/scanners/spinning_lidar.hpp"
#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata {
namespace {

/// One revolution of the simulated 16-beam lidar over a flat yard with a wall: points in the sensor frame.
ScanEvent simulated_revolution(const sim::SpinningLidarConfig& config) {
  sim::WorldDescription d;
  d.boxes.push_back({"ground", {0, 0, -0.1}, {80, 80, 0.2}, 0.0});
  d.boxes.push_back({"wall", {6, 0, 1.0}, {0.2, 20, 2.0}, 0.0});
  const sim::World world(std::move(d));
  sim::SpinningLidar lidar(config, 1);
  for (double t = 0.0; t < 0.2; t += 0.01) {
    if (auto scan = lidar.advance(world, Eigen::Isometry3d::Identity(), t, t + 0.01))
      return std::move(*scan);
  }
  ADD_FAILURE() << "no revolution";
  return {};
}

TEST(SensorMount, TheSimulatedLidarsHeightIsFoundFromTheGround) {
  sim::SpinningLidarConfig config;
  config.mount = Eigen::Vector3d(0.0, 0.0, 1.4);
  ScanEvent scan = simulated_revolution(config);
  SensorMount mount(std::nullopt, "test");
  mount.apply(scan);
  ASSERT_TRUE(mount.mount().has_value());
  EXPECT_TRUE(mount.estimated());
  EXPECT_NEAR(scan.sensor_to_base.translation().z(), 1.4, 0.03);
  EXPECT_NEAR(Eigen::AngleAxisd(scan.sensor_to_base.linear()).angle(), 0.0, 0.5 * M_PI / 180.0);
  // Later scans take the same mount without looking again.
  ScanEvent next = simulated_revolution(config);
  mount.apply(next);
  EXPECT_TRUE(next.sensor_to_base.isApprox(scan.sensor_to_base));
}

TEST(SensorMount, AGivenMountIsKeptAsGiven) {
  const Eigen::Isometry3d given(Eigen::Translation3d(0.1, 0.0, 0.9));
  ScanEvent scan = simulated_revolution({});
  SensorMount mount(given, "test");
  mount.apply(scan);
  EXPECT_FALSE(mount.estimated());
  EXPECT_TRUE(scan.sensor_to_base.isApprox(given));
}

TEST(SensorMount, NoGroundInSightKeepsTheSensorsFrameAndGivesUp) {
  SensorMount mount(std::nullopt, "test");
  for (std::size_t i = 0; i < SensorMount::kScansToTry + 2; ++i) {
    ScanEvent scan;
    scan.points = {{1.0f, 0.0f, 2.0f}, {0.0f, 1.0f, 2.0f}};  // a ceiling, nothing below
    mount.apply(scan);
    EXPECT_TRUE(scan.sensor_to_base.isApprox(Eigen::Isometry3d::Identity()));
  }
  EXPECT_FALSE(mount.mount().has_value());
}

TEST(SensorMount, TheHdl32eOverItsRoad) {
  const std::filesystem::path dir = lidar::test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "hdl32_example.pcap");
  lidar::PcapScanSource source(dir / "hdl32_example.pcap",
                               lidar::LidarSetup{lidar::LidarModel::kHdl32e, dir / "32db.yaml"});
  std::optional<ScanEvent> scan = source.next();
  ASSERT_TRUE(scan.has_value());
  SensorMount mount(std::nullopt, "test");
  mount.apply(*scan);
  ASSERT_TRUE(mount.mount().has_value());
  const Eigen::Isometry3d& found = scan->sensor_to_base;
  const double tilt = Eigen::AngleAxisd(found.linear()).angle() * 180.0 / M_PI;
  std::printf("HDL-32E mount from the road: %.3f m above it, tilted %.2f degrees\n", found.translation().z(),
              tilt);
  // On a car's roof, nearly level (the capture's road is flat around the car).
  EXPECT_GT(found.translation().z(), 1.5);
  EXPECT_LT(found.translation().z(), 2.6);
  EXPECT_LT(tilt, 5.0);
}

}  // namespace
}  // namespace strata

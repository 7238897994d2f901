#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/points/deskew.hpp"
#include "drivers/sim/scanners/spinning_lidar.hpp"
#include "drivers/sim/scanners/tilting_scanner.hpp"

namespace strata::sim {
namespace {

// A closed 10 x 10 x 3 m room (walls 0.2 m thick) on a flat floor at z = 0, and an open variant.
World room(bool with_roof) {
  WorldDescription d;
  d.boxes.push_back({"floor", {0, 0, -0.1}, {10.4, 10.4, 0.2}, 0.0});
  d.boxes.push_back({"north", {0, 5.1, 1.5}, {10.4, 0.2, 3}, 0.0});
  d.boxes.push_back({"south", {0, -5.1, 1.5}, {10.4, 0.2, 3}, 0.0});
  d.boxes.push_back({"east", {5.1, 0, 1.5}, {0.2, 10.4, 3}, 0.0});
  d.boxes.push_back({"west", {-5.1, 0, 1.5}, {0.2, 10.4, 3}, 0.0});
  if (with_roof)
    d.boxes.push_back({"roof", {0, 0, 3.1}, {10.4, 10.4, 0.2}, 0.0});
  return World(std::move(d));
}

// Every point of a scan from the room's centre lies on a wall, the floor or the roof.
void expect_on_room_surfaces(const ScanEvent& scan, const Eigen::Vector3d& sensor_position,
                             double tolerance) {
  for (const Eigen::Vector3f& local : scan.points) {
    const Eigen::Vector3d p = sensor_position + local.cast<double>();
    const double to_wall = std::min(5.0 - std::abs(p.x()), 5.0 - std::abs(p.y()));
    const double to_floor_or_roof = std::min(std::abs(p.z()), std::abs(p.z() - 3.0));
    ASSERT_LT(std::min(to_wall, to_floor_or_roof), tolerance) << p.transpose();
  }
}

TEST(TiltingScanner, NoiselessRangesAreExact) {
  const World world = room(true);
  TiltingScannerConfig config;
  config.beam.range_stddev = 0.0;
  TiltingScanner scanner(config, 1);
  const ScanEvent scan = scanner.scan(world, Eigen::Isometry3d::Identity());  // sensor at the mount height
  EXPECT_EQ(scan.rays, 360u * 181u);
  EXPECT_EQ(scan.points.size(), scan.rays);  // a closed room: every beam returns
  expect_on_room_surfaces(scan, config.mount, 1e-6);
  EXPECT_NEAR(scanner.duration(), 360 / 75.0, 1e-12);
}

TEST(TiltingScanner, NoiseHasTheConfiguredSpread) {
  const World world = room(true);
  TiltingScannerConfig config;
  config.beam.range_stddev = 0.02;
  TiltingScanner noisy(config, 5);
  config.beam.range_stddev = 0.0;
  TiltingScanner exact(config, 5);
  const ScanEvent a = noisy.scan(world, Eigen::Isometry3d::Identity());
  const ScanEvent b = exact.scan(world, Eigen::Isometry3d::Identity());
  ASSERT_EQ(a.points.size(), b.points.size());
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const double error = a.points[i].cast<double>().norm() - b.points[i].cast<double>().norm();
    sum_sq += error * error;
  }
  EXPECT_NEAR(std::sqrt(sum_sq / static_cast<double>(a.points.size())), 0.02, 0.001);
}

TEST(TiltingScanner, NoReturnReadsMaxRangeLikeTheLms) {
  const World world = room(false);  // open to the sky
  TiltingScannerConfig config;
  config.beam.range_stddev = 0.0;
  config.beam.no_return = NoReturn::kMaxRange;
  TiltingScanner lms(config, 1);
  const ScanEvent scan = lms.scan(world, Eigen::Isometry3d::Identity());
  EXPECT_EQ(scan.points.size(), scan.rays);
  const auto at_max = std::count_if(scan.points.begin(), scan.points.end(), [](const Eigen::Vector3f& p) {
    return std::abs(p.norm() - 8.1f) < 1e-4f;
  });
  EXPECT_GT(at_max, 1000);  // the beams to the sky

  config.beam.no_return = NoReturn::kDrop;
  TiltingScanner dropping(config, 1);
  const ScanEvent dropped = dropping.scan(world, Eigen::Isometry3d::Identity());
  EXPECT_EQ(dropped.points.size() + static_cast<std::size_t>(at_max), dropped.rays);
}

TEST(TiltingScanner, IncrementalScanEqualsWholeScan) {
  const World world = room(true);
  TiltingScannerConfig config;
  TiltingScanner whole(config, 9);
  TiltingScanner stepped(config, 9);
  const ScanEvent expected = whole.scan(world, Eigen::Isometry3d::Identity());
  stepped.begin(10.0);
  std::optional<ScanEvent> got;
  int steps = 0;
  for (double t = 10.0; !got && steps < 10000; t += 0.01, ++steps) {
    got = stepped.advance(world, Eigen::Isometry3d::Identity(), t, t + 0.01);
  }
  ASSERT_TRUE(got);
  EXPECT_EQ(got->points, expected.points);
  EXPECT_NEAR(steps * 0.01, stepped.duration(), 0.011);
  EXPECT_FALSE(stepped.scanning());
}

TEST(SpinningLidar, RevolutionsAreCompleteAndOnTheSurfaces) {
  const World world = room(true);
  SpinningLidarConfig config;
  config.beam.range_stddev = 0.0;
  SpinningLidar lidar(config, 1);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  std::vector<ScanEvent> scans;
  for (double t = 0.0; t < 0.35; t += 0.01) {
    if (auto scan = lidar.advance(world, base, t, t + 0.01))
      scans.push_back(std::move(*scan));
  }
  ASSERT_EQ(scans.size(), 3u);  // revolutions end at 0.1, 0.2, 0.3 s
  for (const auto& scan : scans) {
    EXPECT_EQ(scan.rays, 16u * 1800u);
    EXPECT_EQ(scan.points.size(), scan.rays);
    expect_on_room_surfaces(scan, config.mount, 1e-6);
  }
  EXPECT_NEAR(scans[1].stamp - scans[0].stamp, 0.1, 1e-9);
  // Each point says when it was measured: the revolution's first column a period before its end, the
  // last one firing interval before.
  for (const auto& scan : scans) {
    ASSERT_EQ(scan.point_times.size(), scan.points.size());
    EXPECT_NEAR(scan.point_times.front(), -0.1, 1e-6);
    EXPECT_NEAR(scan.point_times.back(), -0.1 / 1800.0, 1e-6);
    EXPECT_TRUE(std::is_sorted(scan.point_times.begin(), scan.point_times.end()));
  }
  // The 16 beams span -15 to +15 degrees.
  float lowest = 1, highest = -1;
  for (const auto& p : scans[0].points) {
    lowest = std::min(lowest, p.z() / p.norm());
    highest = std::max(highest, p.z() / p.norm());
  }
  EXPECT_NEAR(std::asin(lowest), -15 * 3.14159265 / 180, 1e-4);
  EXPECT_NEAR(std::asin(highest), 15 * 3.14159265 / 180, 1e-4);
}

TEST(SpinningLidar, ARevolutionTakenWhileDrivingIsOnTheSurfacesOnceDeskewed) {
  // Driving 1.5 m/s and turning 1 rad/s through the room: each firing sees it from where the base is
  // then. The revolution's points, from the pose at its end, are smeared off the walls; deskewed with
  // the motion and their times, they are on them again (to within the 1 ms steps the base moves in).
  const World world = room(true);
  SpinningLidarConfig config;
  config.beam.range_stddev = 0.0;
  SpinningLidar lidar(config, 1);
  const Pose2 velocity{1.5, 0.0, 1.0};
  const auto base_at = [&](double t) {
    const Pose2 pose = Pose2{-1.0, -1.0, 0.3}.compose(pose_after(velocity, t));
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.linear() = Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    base.translation() = Eigen::Vector3d(pose.x, pose.y, 0.0);
    return base;
  };
  std::optional<ScanEvent> scan;
  double t = 0.0;
  for (; !scan; t += 0.001)
    scan = lidar.advance(world, base_at(t), t, t + 0.001);
  ScanEvent& revolution = *scan;
  PointCloud points;
  for (const Eigen::Vector3f& p : revolution.points)
    points.push_back(revolution.sensor_to_base * p.cast<double>());
  const Eigen::Isometry3d end = base_at(revolution.stamp);
  const auto largest_miss = [&](const PointCloud& in_base) {
    double largest = 0.0;
    for (const Eigen::Vector3d& local : in_base) {
      const Eigen::Vector3d p = end * local;
      const double to_wall = std::min(5.0 - std::abs(p.x()), 5.0 - std::abs(p.y()));
      const double to_floor_or_roof = std::min(std::abs(p.z()), std::abs(p.z() - 3.0));
      largest = std::max(largest, std::abs(std::min(to_wall, to_floor_or_roof)));
    }
    return largest;
  };
  EXPECT_GT(largest_miss(points), 0.3);
  deskew(points, revolution.point_times, velocity);
  EXPECT_LT(largest_miss(points), 0.02);
}

TEST(SpinningLidar, DropsNoReturnsAndRespectsMinRange) {
  const World world = room(false);
  SpinningLidarConfig config;
  SpinningLidar lidar(config, 1);
  std::optional<ScanEvent> scan;
  for (double t = 0.0; !scan; t += 0.01)
    scan = lidar.advance(world, Eigen::Isometry3d::Identity(), t, t + 0.01);
  EXPECT_LT(scan->points.size(), scan->rays);  // the upward beams over the 3 m walls see nothing
  for (const auto& p : scan->points)
    EXPECT_GE(p.norm(), 0.4f);
}

TEST(Scanners, SameSeedSameScan) {
  const World world = room(true);
  TiltingScanner a({}, 42);
  TiltingScanner b({}, 42);
  TiltingScanner c({}, 43);
  const auto pa = a.scan(world, Eigen::Isometry3d::Identity()).points;
  EXPECT_EQ(pa, b.scan(world, Eigen::Isometry3d::Identity()).points);
  EXPECT_NE(pa, c.scan(world, Eigen::Isometry3d::Identity()).points);
}

}  // namespace
}  // namespace strata::sim

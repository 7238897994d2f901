// The ground under a sensor (issue 23 item 3): a lidar's height and tilt over the floor it sees, without
// being told, and a clear refusal where there is no floor to see.
#include "core/points/ground_plane.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace strata {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Rings of a floor `height` below a sensor tilted by roll and pitch, with range noise, and what else a room
/// holds: a table top 0.75 m above the floor (a smaller plane) and a wall. Points in the sensor's frame.
std::vector<Eigen::Vector3f> room_scan(double height, double roll, double pitch) {
  const Eigen::Matrix3d sensor_in_base =
      (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  const Eigen::Vector3d sensor(0.0, 0.0, height);
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Eigen::Vector3f> points;
  const auto add = [&](const Eigen::Vector3d& base_point) {
    points.push_back((sensor_in_base.transpose() * (base_point - sensor)).cast<float>());
  };
  for (double r = 3.0; r < 25.0; r *= 1.15) {  // rings, sparser further out
    for (int k = 0; k < 900; ++k) {
      const double a = 2.0 * M_PI * k / 900.0;
      add({r * std::cos(a), r * std::sin(a), noise(random)});
    }
  }
  for (double x = 2.0; x < 3.5; x += 0.05) {  // a table top, 1.5 x 1.5 m
    for (double y = -0.75; y < 0.75; y += 0.05)
      add({x, y, 0.75 + noise(random)});
  }
  for (double y = -10.0; y < 10.0; y += 0.05) {  // a wall 8 m away
    for (double z = 0.0; z < 3.0; z += 0.1)
      add({8.0 + noise(random), y, z});
  }
  return points;
}

TEST(GroundPlane, FindsTheFloorUnderATiltedSensorAndItsHeight) {
  const double height = 1.42, roll = 3.0 * kDeg, pitch = -5.0 * kDeg;
  const auto ground = find_ground_plane(room_scan(height, roll, pitch));
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(ground->height, height, 0.02);  // not the table's 0.67 m
  EXPECT_NEAR(ground->tilt_deg().x(), 3.0, 0.3);
  EXPECT_NEAR(ground->tilt_deg().y(), -5.0, 0.3);
  // The mount puts the floor at the base's z = 0 and the sensor at its height above it.
  const Eigen::Isometry3d mount = ground->sensor_to_base();
  EXPECT_NEAR(mount.translation().z(), height, 0.02);
  const std::vector<Eigen::Vector3f> level = room_scan(height, 0.0, 0.0);
  const std::vector<Eigen::Vector3f> tilted = room_scan(height, roll, pitch);
  for (std::size_t i = 0; i < 900; i += 97) {  // floor points of the first ring, seen both ways
    const Eigen::Vector3d in_base = mount * tilted[i].cast<double>();
    EXPECT_NEAR(in_base.z(), static_cast<double>(level[i].z()) + height, 0.03);
  }
}

TEST(GroundPlane, NoFloorInSightIsRefusedWithTheReason) {
  std::vector<Eigen::Vector3f> ceiling_only;
  for (double x = -10.0; x < 10.0; x += 0.1)
    ceiling_only.emplace_back(static_cast<float>(x), 1.0f, 2.5f);
  std::string why;
  EXPECT_FALSE(find_ground_plane(ceiling_only, {}, &why).has_value());
  EXPECT_NE(why.find("below the sensor"), std::string::npos) << why;

  // Points below, but a slope steeper than any floor: no level plane.
  std::vector<Eigen::Vector3f> steep;
  for (double x = 2.0; x < 20.0; x += 0.1)
    for (double y = -5.0; y < 5.0; y += 0.2)
      steep.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(-0.8 * x));
  EXPECT_FALSE(find_ground_plane(steep, {}, &why).has_value());
  EXPECT_NE(why.find("no level plane"), std::string::npos) << why;
}

TEST(GroundPlane, NonFinitePointsAreIgnored) {
  std::vector<Eigen::Vector3f> points = room_scan(0.8, 0.0, 0.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  points.insert(points.begin(), 500, Eigen::Vector3f(nan, 0.0f, -1.0f));
  const auto ground = find_ground_plane(points);
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(ground->height, 0.8, 0.02);
}

}  // namespace
}  // namespace strata

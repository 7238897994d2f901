#include "drivers/lidar/motion_compensation.hpp"

#include <gtest/gtest.h>

#include <random>

namespace strata::lidar {
namespace {

/// A sensor driving at 2 m/s along x, climbing 0.3 m/s and turning at 1 rad/s.
Eigen::Isometry3d moving_sensor(double time) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(2.0 * time, 0.5 * time * time, 0.3 * time);
  pose.linear() = Eigen::AngleAxisd(1.0 * time, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

TEST(MotionCompensation, ASweepTakenWhileMovingIsReExpressedAtItsEnd) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(-20.0, 20.0);
  std::vector<Eigen::Vector3d> world;
  std::vector<LidarPoint> points;
  for (int i = 0; i < 2000; ++i) {
    const double time = 0.1 * i / 1999.0;  // one 10 Hz revolution
    const Eigen::Vector3d at(coordinate(random), coordinate(random), coordinate(random) / 10.0);
    world.push_back(at);
    points.push_back(LidarPoint{(moving_sensor(time).inverse() * at).cast<float>(), 0.0f, time, 0});
  }
  const double end = 0.1;
  const SensorPoseAt pose_at = [](double time) -> std::optional<Eigen::Isometry3d> {
    return moving_sensor(time);
  };
  // Uncompensated, the early points are off by the distance travelled: ~0.2 m and 0.1 rad.
  double error_before = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
    error_before = std::max(
        error_before, (points[i].position.cast<double>() - moving_sensor(end).inverse() * world[i]).norm());
  EXPECT_GT(error_before, 0.2);
  ASSERT_TRUE(compensate_motion(points, end, pose_at));
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_LT((points[i].position.cast<double>() - moving_sensor(end).inverse() * world[i]).norm(), 2e-3)
        << i;
}

TEST(MotionCompensation, UnknownPosesLeaveThePointsAlone) {
  std::vector<LidarPoint> points{{Eigen::Vector3f(1, 2, 3), 0.0f, 1.0, 0},
                                 {Eigen::Vector3f(4, 5, 6), 0.0f, 1.1, 0}};
  PoseHistory history;
  history.add(1.05, Eigen::Isometry3d::Identity());
  history.add(1.2, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(compensate_motion(points, 1.1, [&](double t) { return history.at(t); }));  // 1.0 not covered
  EXPECT_EQ(points[0].position, Eigen::Vector3f(1, 2, 3));
}

TEST(PoseHistory, InterpolatesBetweenPosesAndNeverExtrapolates) {
  PoseHistory history;
  history.add(1.0, moving_sensor(0.0));
  history.add(2.0, moving_sensor(1.0));
  EXPECT_FALSE(history.at(0.5));
  EXPECT_FALSE(history.at(2.5));
  const std::optional<Eigen::Isometry3d> middle = history.at(1.5);
  ASSERT_TRUE(middle);
  EXPECT_NEAR(middle->translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(middle->rotation()).angle(), 0.5, 1e-9);
  EXPECT_TRUE(history.at(2.0)->isApprox(moving_sensor(1.0)));
  history.add(3.0, moving_sensor(2.0));
  history.drop_before(2.5);
  EXPECT_EQ(history.size(), 2u);
  EXPECT_TRUE(history.at(2.7));
}

}  // namespace
}  // namespace strata::lidar

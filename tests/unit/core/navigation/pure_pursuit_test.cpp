#include "core/navigation/pure_pursuit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace strata {
namespace {

/// Drives an ideal unicycle with the follower's commands until it says it arrived (or time runs out).
struct Trajectory {
  Pose3 pose;
  bool arrived = false;
  double seconds = 0.0;
  double farthest_from_path = 0.0;
};

Trajectory follow(PurePursuit& follower, Pose3 pose, const std::vector<Eigen::Vector3d>& path,
                  double limit = 120.0) {
  constexpr double dt = 0.05;
  Trajectory run;
  for (double t = 0.0; t < limit; t += dt) {
    const PurePursuit::Output output = follower.update(pose);
    if (output.arrived) {
      run.arrived = true;
      break;
    }
    pose.yaw += output.command.w * dt;
    pose.position.x() += output.command.v * std::cos(pose.yaw) * dt;
    pose.position.y() += output.command.v * std::sin(pose.yaw) * dt;
    run.seconds = t;
    double nearest = 1e9;
    for (const Eigen::Vector3d& p : path)
      nearest = std::min(nearest, (p.head<2>() - pose.position.head<2>()).norm());
    run.farthest_from_path = std::max(run.farthest_from_path, nearest);
  }
  run.pose = pose;
  return run;
}

std::vector<Eigen::Vector3d> straight(double length, double spacing = 0.1) {
  std::vector<Eigen::Vector3d> path;
  for (double s = 0.0; s <= length + 1e-9; s += spacing)
    path.emplace_back(s, 0.0, 0.0);
  return path;
}

TEST(PurePursuit, StraightPathStopsWithinToleranceAtTheEnd) {
  PurePursuit follower;
  const auto path = straight(6.0);
  follower.set_path(path);
  const Trajectory run = follow(follower, {}, path);
  ASSERT_TRUE(run.arrived);
  EXPECT_LT((run.pose.position.head<2>() - Eigen::Vector2d(6.0, 0.0)).norm(),
            follower.config().goal_tolerance);
  EXPECT_LT(run.farthest_from_path, 0.05);
}

TEST(PurePursuit, CurvedPathIsFollowedClosely) {
  std::vector<Eigen::Vector3d> path;  // a quarter circle of radius 3 after a straight start
  for (double s = 0.0; s < 2.0; s += 0.1)
    path.emplace_back(s, 0.0, 0.0);
  for (double a = 0.0; a <= std::numbers::pi / 2 + 1e-9; a += 0.03)
    path.emplace_back(2.0 + 3.0 * std::sin(a), 3.0 - 3.0 * std::cos(a), 0.0);
  PurePursuit follower;
  follower.set_path(path);
  const Trajectory run = follow(follower, {}, path);
  ASSERT_TRUE(run.arrived);
  EXPECT_LT((run.pose.position.head<2>() - path.back().head<2>()).norm(), follower.config().goal_tolerance);
  EXPECT_LT(run.farthest_from_path, 0.25);  // pure pursuit cuts corners a little, never far
}

TEST(PurePursuit, PathBehindTheRobotIsTurnedToOnTheSpot) {
  PurePursuit follower;
  const auto path = straight(4.0);
  follower.set_path(path);
  Pose3 facing_away;
  facing_away.yaw = std::numbers::pi;
  const PurePursuit::Output first = follower.update(facing_away);
  EXPECT_EQ(first.command.v, 0.0);
  EXPECT_NE(first.command.w, 0.0);
  const Trajectory run = follow(follower, facing_away, path);
  EXPECT_TRUE(run.arrived);
}

TEST(PurePursuit, SlowsDownNearTheGoal) {
  PurePursuit follower;
  const auto path = straight(10.0);
  follower.set_path(path);
  Pose3 far;
  Pose3 near;
  near.position.x() = 9.5;
  follower.set_path(path);
  const double cruising = follower.update(far).command.v;
  const double arriving = follower.update(near).command.v;
  EXPECT_NEAR(cruising, follower.config().cruise_speed, 1e-9);
  EXPECT_LT(arriving, cruising);
  EXPECT_GE(arriving, follower.config().min_speed);
}

TEST(PurePursuit, WithoutAPathItStops) {
  PurePursuit follower;
  const PurePursuit::Output output = follower.update({});
  EXPECT_TRUE(output.arrived);
  EXPECT_EQ(output.command.v, 0.0);
  EXPECT_EQ(output.command.w, 0.0);
}

TEST(PurePursuit, APathThatPassesUnderItselfIsFollowedInOrder) {
  // Out east on the ground, back west on a deck 3 m above the same line: near the start the deck part is
  // as close in the plane as the ground part, but the robot is on the ground.
  std::vector<Eigen::Vector3d> path;
  for (double s = 0.0; s <= 5.0 + 1e-9; s += 0.1)
    path.emplace_back(s, 0.0, 0.0);
  for (double s = 5.0; s >= 1.0 - 1e-9; s -= 0.1)
    path.emplace_back(s, 0.02, 3.0);
  PurePursuit follower;
  follower.set_path(path);
  const PurePursuit::Output output = follower.update({});
  EXPECT_FALSE(output.arrived);
  EXPECT_GT(output.command.v, 0.0);  // heads east along the ground part
  EXPECT_GT(output.remaining, 8.0);
}

}  // namespace
}  // namespace strata

#include "server/pipeline/navigator.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "core/mls/drivable_map.hpp"
#include "tests/support/navigation_scenes.hpp"

namespace strata::pipeline {
namespace {

using namespace std::chrono_literals;

/// A steady clock the test moves by hand.
struct ManualClock {
  std::chrono::steady_clock::time_point now{};
  Navigator::Clock function() {
    return [this] { return now; };
  }
};

Pose3 at(double x, double y, double z, double yaw = 0.0) {
  Pose3 pose;
  pose.position = {x, y, z};
  pose.yaw = yaw;
  return pose;
}

void publish(Navigator& navigator, const MlsMap& map, std::uint64_t version = 1) {
  const DrivableMap drivable;
  navigator.on_map_update({map, drivable, Eigen::Vector3d::Zero(), version});
}

/// wall_and_stairs_scene with a wall across the way north from (-2, -4): no way left.
MlsMap way_closed() {
  MlsMap closed = test::wall_and_stairs_scene();
  PointCloud wall;
  test::add_vertical_face(wall, -3.0, 0.0, 2.0, 0.0, 0.0, 2.0);
  closed.insert_scan(wall, {0, 0, 3});
  return closed;
}

TEST(Navigator, LeavesTheRobotAloneUntilAnOperatorCommands) {
  Navigator navigator;
  EXPECT_FALSE(navigator.drive(at(0, 0, 0), 0.0).has_value());
  EXPECT_EQ(navigator.goal_status().id, 0U);
  EXPECT_EQ(navigator.path(), nullptr);
}

TEST(Navigator, GoalWithoutAMapFailsWithNoMap) {
  Navigator navigator;
  ASSERT_TRUE(navigator.set_goal({1.0, 2.0, {}}).ok);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kAccepted);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "no_map");
  const auto command = navigator.drive(at(0, 0, 0), 1.0);
  ASSERT_TRUE(command.has_value());  // an operator asked: the demo is over, the robot stands
  EXPECT_EQ(command->v, 0.0);
  EXPECT_EQ(command->w, 0.0);
}

TEST(Navigator, BadInputIsRefusedAndChangesNothing) {
  Navigator navigator;
  const CommandResult goal = navigator.set_goal({std::nan(""), 2.0, {}});
  EXPECT_FALSE(goal.ok);
  EXPECT_EQ(goal.code, ErrorCode::kBadParams);
  EXPECT_FALSE(navigator.teleop(std::numeric_limits<double>::infinity(), 0.0).ok);
  EXPECT_EQ(navigator.goal_status().id, 0U);
  EXPECT_FALSE(navigator.drive(at(0, 0, 0), 0.0).has_value());
}

TEST(Navigator, PlansDrivesAndReportsTheGoalReached) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0, M_PI), 0.0);
  ASSERT_TRUE(navigator.set_goal({2.05, 0.05, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  const auto path = navigator.path();
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(path->goal_id, navigator.goal_status().id);
  EXPECT_NEAR(path->length, 3.0, 1e-6);
  const auto command = navigator.drive(at(5.05, 0.05, 0.0, M_PI), 0.1);
  ASSERT_TRUE(command.has_value());
  EXPECT_GT(command->v, 0.0);
  (void)navigator.drive(at(2.1, 0.05, 0.0, M_PI), 5.0);  // there
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kReached);
  EXPECT_EQ(navigator.goal_status().stamp, 5.0);
  EXPECT_EQ(navigator.path(), nullptr);
}

TEST(Navigator, UnreachableGoalFails) {
  const MlsMap map = test::wall_and_stairs_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(0.05, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({2.45, 0.05, 0.3}).ok);  // on a stair
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "goal_not_drivable");
  // In words, with where the robot could go instead: the floor before the stairs.
  const std::string& message = navigator.goal_status().message;
  EXPECT_EQ(message.rfind("the goal is not a drivable place with room for the robot; the nearest place the "
                          "robot can reach is (",
                          0),
            0U)
      << message;
  ASSERT_TRUE(navigator.set_goal({40.0, 0.0, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().reason, "off_map");
  EXPECT_EQ(navigator.goal_status().message, "the goal is outside the known map");
}

TEST(Navigator, AGoalBesideAWallDrivesToTheNearestPlaceWithRoomAndSaysWhere) {
  const MlsMap map = test::wall_and_stairs_scene();  // a wall at x = -3
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(0.05, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({-2.85, 0.05, {}}).ok);  // 0.15 m from the wall: no room for the robot
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  const std::string& message = navigator.goal_status().message;
  EXPECT_EQ(
      message.rfind("the spot asked for is too near an edge for the robot: driving to the nearest place "
                    "with room, (",
                    0),
      0U)
      << message;
  const auto path = navigator.path();
  ASSERT_NE(path, nullptr);
  EXPECT_GT(path->points.back().x(), -2.85);
  (void)navigator.drive(at(path->points.back().x(), path->points.back().y(), 0.0, M_PI), 5.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kReached);
}

/// A hall's floor (z = 0, x in [-10, 10], y in [-3, 3]) that goes on east as a passage 0.6 m wide (walls at
/// y = +-0.3 from x = 10 to 13), too narrow for the robot: its nearest place with room is ~0.4 m west of x
/// = 10.
MlsMap hall_with_a_narrow_passage() {
  MlsMap map(test::scene_config());
  PointCloud points;
  test::add_plane(points, -10, 10, -3, 3, 0.0);
  test::add_plane(points, 10, 13, -0.3, 0.3, 0.0);
  test::add_vertical_face(points, 10, -0.3, 13, -0.3, 0.0, 2.0);
  test::add_vertical_face(points, 10, 0.3, 13, 0.3, 0.0, 2.0);
  map.insert_scan(points, {0, 0, 3});
  return map;
}

// A spot in the passage, 1.4 m from room: from 3 m it is refused, from 19 m (where the live map knows the
// ground only between a scanner's rings) it moves to room, and it stays accepted once the robot is near.
TEST(Navigator, AFarGoalMayMoveFurtherToRoomAndStaysAcceptedFromNear) {
  MlsMap map = hall_with_a_narrow_passage();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(8.0, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({11.0, 0.05, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().reason, "goal_not_drivable");

  (void)navigator.drive(at(-8.0, 0.05, 0.0), 1.0);
  ASSERT_TRUE(navigator.set_goal({11.0, 0.05, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  ASSERT_EQ(navigator.goal_status().phase, GoalPhase::kDriving) << navigator.goal_status().message;
  const auto path = navigator.path();
  ASSERT_NE(path, nullptr);
  EXPECT_LT(path->points.back().x(), 10.0);
  EXPECT_GT(path->points.back().x(), 9.0);

  (void)navigator.drive(at(8.0, 0.05, 0.0), 20.0);
  publish(navigator, map, 2);
  EXPECT_TRUE(navigator.plan_pending());  // a replan from near
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving) << navigator.goal_status().message;
  ASSERT_NE(navigator.path(), nullptr);
  EXPECT_GT(navigator.path()->points.back().x(), 9.0);
}

TEST(Navigator, ANewGoalReplacesTheOldAndCancelStops) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({8.05, 0.05, {}}).ok);
  const auto first = navigator.goal_status().id;
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_TRUE(navigator.set_goal({5.05, 4.05, {}}).ok);
  const auto second = navigator.goal_status().id;
  EXPECT_NE(first, second);
  EXPECT_EQ(navigator.path(), nullptr);  // the old path is gone with its goal
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_NE(navigator.path(), nullptr);
  EXPECT_EQ(navigator.path()->goal_id, second);
  EXPECT_NE(navigator.drive(at(5.05, 0.05, 0.0), 0.1)->w, 0.0);  // turning north

  ASSERT_TRUE(navigator.cancel_goal().ok);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kCancelled);
  EXPECT_EQ(navigator.path(), nullptr);
  const auto command = navigator.drive(at(5.05, 0.05, 0.0), 0.2);
  ASSERT_TRUE(command.has_value());
  EXPECT_EQ(command->v, 0.0);
  EXPECT_EQ(command->w, 0.0);
  EXPECT_FALSE(navigator.plan_pending());  // nothing to plan for
}

// The WebSocket operator connection that set a goal closed: its goal is cancelled with a reason and the
// robot stops, but only while it is still the goal being driven; one replaced since is left alone.
TEST(Navigator, CancelIfActiveCancelsOnlyThatGoal) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0), 0.0);
  const CommandResult first = navigator.set_goal({8.05, 0.05, {}});
  ASSERT_TRUE(first.ok);
  EXPECT_EQ(first.goal_id, navigator.goal_status().id);
  const CommandResult second = navigator.set_goal({5.05, 4.05, {}});
  ASSERT_TRUE(second.ok);
  EXPECT_NE(second.goal_id, first.goal_id);
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_NE(navigator.path(), nullptr);

  EXPECT_FALSE(navigator.cancel_goal_if_active(first.goal_id, "operator_disconnected"));  // replaced
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  EXPECT_TRUE(navigator.goal_status().reason.empty());
  ASSERT_NE(navigator.path(), nullptr);

  EXPECT_TRUE(navigator.cancel_goal_if_active(second.goal_id, "operator_disconnected"));
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kCancelled);
  EXPECT_EQ(navigator.goal_status().reason, "operator_disconnected");
  EXPECT_EQ(navigator.path(), nullptr);
  const auto command = navigator.drive(at(5.05, 0.05, 0.0), 0.2);
  ASSERT_TRUE(command.has_value());
  EXPECT_EQ(command->v, 0.0);
  EXPECT_EQ(command->w, 0.0);
  EXPECT_FALSE(navigator.cancel_goal_if_active(second.goal_id, "operator_disconnected"));  // done already

  // A new goal starts without the old reason.
  ASSERT_TRUE(navigator.set_goal({8.05, 0.05, {}}).ok);
  EXPECT_TRUE(navigator.goal_status().reason.empty());
}

TEST(Navigator, ReplansWhenANewMapArrives) {
  MlsMap map = test::wall_and_stairs_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(-2.0, -4.0, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  ASSERT_TRUE(navigator.plan_pending());
  const auto before = navigator.path();
  ASSERT_NE(before, nullptr);
  EXPECT_NEAR(before->length, 8.0, 0.1);
  // A new scan shows a wall across the way with a gap at its east end: the path bends round it.
  PointCloud wall;
  test::add_vertical_face(wall, -3.0, 0.0, 0.0, 0.0, 0.0, 2.0);
  map.insert_scan(wall, {0, 0, 3});
  publish(navigator, map, 2);
  EXPECT_TRUE(navigator.plan_pending());
  const auto after = navigator.path();
  ASSERT_NE(after, nullptr);
  EXPECT_GT(after->version, before->version);
  EXPECT_GT(after->length, before->length + 1.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  // And when the gap closes too, the robot stops and, when no map opens a way in the grace time, the goal
  // fails as blocked.
  PointCloud closing;
  test::add_vertical_face(closing, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0);
  map.insert_scan(closing, {0, 0, 3});
  publish(navigator, map, 3);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  EXPECT_EQ(navigator.path(), nullptr);
  EXPECT_NE(navigator.goal_status().message.find("waiting"), std::string::npos);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0), 1.0)->v, 0.0);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0), 19.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0), 22.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "blocked");
}

TEST(Navigator, AWayClosedForAMomentIsDrivenOnWhenTheMapOpensItAgain) {
  // As after a loop closure: the pose moves before the rebuilt map arrives, and for a few seconds the map
  // the planner has shows no way from where the robot now is.
  const MlsMap open = test::wall_and_stairs_scene();
  Navigator navigator;
  publish(navigator, open);
  (void)navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 0.0);
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_NE(navigator.path(), nullptr);

  const MlsMap closed = way_closed();
  publish(navigator, closed, 2);
  ASSERT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.path(), nullptr);
  for (double t = 1.0; t < 18.0; t += 1.0)  // stopped, and not taken for stuck
    EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), t)->v, 0.0);

  publish(navigator, open, 3);
  ASSERT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  EXPECT_EQ(navigator.goal_status().message, "the way is open again");
  ASSERT_NE(navigator.path(), nullptr);
  EXPECT_GT(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 18.5)->v, 0.0);
  // Once the way opened, the wait no longer counts: past the grace time the goal still drives.
  EXPECT_GT(navigator.drive(at(-2.0, -3.5, 0.0, M_PI / 2), 30.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
}

TEST(Navigator, ABlockedGoalWaitsForTheRebuildUnderWayPastTheGrace) {
  // The lidar demo at 5x (issue 58): blocked after a loop closure moved the pose, the goal failed while the
  // rebuilt map that opened the way again was still being built (4 s of wall time, 20 s of robot time).
  const MlsMap open = test::wall_and_stairs_scene();
  const MlsMap closed = way_closed();
  Navigator navigator;
  publish(navigator, open);
  (void)navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 0.0);
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  ASSERT_TRUE(navigator.plan_pending());
  publish(navigator, closed, 2);
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_EQ(navigator.path(), nullptr);  // blocked from t = 0

  navigator.map_rebuilding(true);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 25.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving) << "a rebuild is under way";
  publish(navigator, open, 3);
  navigator.map_rebuilding(false);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 26.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving) << "the rebuilt map is not judged yet";
  ASSERT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().message, "the way is open again");
  EXPECT_GT(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 26.5)->v, 0.0);

  // A rebuilt map that keeps the way closed: the goal fails once it is judged, the grace long past.
  publish(navigator, closed, 4);
  ASSERT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 27.0)->v, 0.0);
  navigator.map_rebuilding(true);
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 50.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  publish(navigator, closed, 5);
  navigator.map_rebuilding(false);
  ASSERT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 51.0)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "blocked");
}

TEST(Navigator, ANewGoalTheMapBeforeALoopClosureRefusesIsJudgedOnTheRebuiltMap) {
  // The lidar demo (issue 58): a loop closure corrected 0.8 m of drift; while the map was rebuilt from the
  // moved keyframes, the old one showed no way down the ramp, and the goal was refused 3 s before the
  // rebuilt map, which planned it, arrived.
  const MlsMap open = test::wall_and_stairs_scene();
  const MlsMap closed = way_closed();
  Navigator navigator;
  publish(navigator, closed);
  (void)navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 0.0);

  navigator.map_rebuilding(true);
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kPlanning) << navigator.goal_status().message;
  EXPECT_FALSE(navigator.plan_pending()) << "nothing to plan until the rebuild is over";
  EXPECT_EQ(navigator.drive(at(-2.0, -4.0, 0.0, M_PI / 2), 1.0)->v, 0.0);
  publish(navigator, open, 2);
  navigator.map_rebuilding(false);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  ASSERT_NE(navigator.path(), nullptr);
  EXPECT_NEAR(navigator.path()->length, 8.0, 0.1);

  // The rebuilt map refuses it too: it fails then. And without a rebuild under way, at once.
  navigator.map_rebuilding(true);
  publish(navigator, closed, 3);
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kPlanning);
  navigator.map_rebuilding(false);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "no_connection");
  ASSERT_TRUE(navigator.set_goal({-2.0, 4.0, {}}).ok);
  EXPECT_TRUE(navigator.plan_pending());
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
}

TEST(Navigator, TeleopLastsHalfASecondUnlessRenewed) {
  ManualClock clock;
  Navigator navigator({}, clock.function());
  ASSERT_TRUE(navigator.teleop(0.4, 0.2).ok);
  auto command = navigator.drive(at(0, 0, 0), 0.0);
  ASSERT_TRUE(command.has_value());
  EXPECT_EQ(command->v, 0.4);
  EXPECT_EQ(command->w, 0.2);
  clock.now += 400ms;
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 0.4)->v, 0.4);
  ASSERT_TRUE(navigator.teleop(0.3, 0.0).ok);  // renewed
  clock.now += 400ms;
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 0.8)->v, 0.3);
  clock.now += 200ms;
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 1.0)->v, 0.0);  // expired

  ASSERT_TRUE(navigator.teleop(5.0, -9.0).ok);  // clamped to the base's limits
  command = navigator.drive(at(0, 0, 0), 1.1);
  EXPECT_EQ(command->v, 1.0);
  EXPECT_EQ(command->w, -1.2);
  navigator.stop_teleop();
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 1.2)->v, 0.0);  // at once
}

TEST(Navigator, TeleopsLeaseRunsFromWhenItWasSent) {
  ManualClock clock;
  Navigator navigator({}, clock.function());
  ASSERT_TRUE(navigator.teleop(0.4, 0.0, clock.now - 300ms).ok);  // 300 ms in the network
  clock.now += 150ms;
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 0.0)->v, 0.4);
  clock.now += 100ms;  // 550 ms after it was sent
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 0.1)->v, 0.0);
  ASSERT_TRUE(navigator.teleop(0.4, 0.0, clock.now + 5s).ok);  // a clock ahead counts as sent now
  clock.now += 600ms;
  EXPECT_EQ(navigator.drive(at(0, 0, 0), 0.7)->v, 0.0);
}

TEST(Navigator, TeleopCancelsTheGoal) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({8.05, 0.05, {}}).ok);
  ASSERT_TRUE(navigator.plan_pending());
  ASSERT_TRUE(navigator.teleop(0.2, 0.0).ok);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kCancelled);
  EXPECT_EQ(navigator.path(), nullptr);
}

TEST(Navigator, ARobotThatDoesNotMoveFailsAsStuck) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0), 0.0);
  ASSERT_TRUE(navigator.set_goal({8.05, 0.05, {}}).ok);
  ASSERT_TRUE(navigator.plan_pending());
  for (double t = 0.0; t < 19.0; t += 1.0)  // bumped into something the map does not show
    EXPECT_GT(navigator.drive(at(5.1, 0.05, 0.0), t)->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  const auto command = navigator.drive(at(5.1, 0.05, 0.0), 21.0);
  EXPECT_EQ(command->v, 0.0);
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kFailed);
  EXPECT_EQ(navigator.goal_status().reason, "stuck");
}

TEST(Navigator, PlansOnItsOwnThread) {
  const MlsMap map = test::bridge_scene();
  Navigator navigator;
  publish(navigator, map);
  (void)navigator.drive(at(5.05, 0.05, 0.0), 0.0);
  navigator.start();
  ASSERT_TRUE(navigator.set_goal({8.05, 0.05, {}}).ok);
  // No timing assumption: wait for the phase, however long the planning thread takes.
  while (navigator.goal_status().phase == GoalPhase::kAccepted ||
         navigator.goal_status().phase == GoalPhase::kPlanning)
    std::this_thread::yield();
  EXPECT_EQ(navigator.goal_status().phase, GoalPhase::kDriving);
  navigator.stop();
}

}  // namespace
}  // namespace strata::pipeline

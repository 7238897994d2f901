#include "core/navigation/patch_graph_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/support/navigation_scenes.hpp"

namespace strata {
namespace {

double highest(const PatchPath& path) {
  double z = -1e9;
  for (const auto& p : path.points)
    z = std::max(z, p.z());
  return z;
}

TEST(PatchGraphPlanner, GoalOnTheDeckIsReachedOverTheRamp) {
  const MlsMap map = test::bridge_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath path = plan_on_patches(graph, {5, 0, 0}, {.x = 0.05, .y = 0.05, .z = 1.5});
  ASSERT_TRUE(path.found()) << describe(path.status);
  EXPECT_NEAR(path.points.back().z(), 1.5, 0.05);
  EXPECT_NEAR(path.points.front().z(), 0.0, 0.05);
  // Around to the ramp's foot (y = 20), up it, back south along the deck.
  const bool climbed_the_ramp = std::any_of(path.points.begin(), path.points.end(), [](const auto& p) {
    return p.y() > 12 && p.y() < 18 && p.z() > 0.2 && p.z() < 1.3;
  });
  EXPECT_TRUE(climbed_the_ramp);
  EXPECT_GT(path.length, 35.0);
}

TEST(PatchGraphPlanner, GoalOnTheRoadUnderTheDeckGoesUnder) {
  const MlsMap map = test::bridge_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath path = plan_on_patches(graph, {5, 0, 0}, {.x = -5.05, .y = 0.05, .z = 0.0});
  ASSERT_TRUE(path.found()) << describe(path.status);
  EXPECT_LT(highest(path), 0.05);
  EXPECT_NEAR(path.length, 10.1, 0.2);  // straight under the deck
}

TEST(PatchGraphPlanner, WithoutAHeightTheGoalIsOnTheRobotsLevel) {
  const MlsMap map = test::bridge_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath on_deck = plan_on_patches(graph, {0.05, -3.05, 1.5}, {.x = 0.05, .y = 3.05});
  ASSERT_TRUE(on_deck.found()) << describe(on_deck.status);
  EXPECT_NEAR(on_deck.points.back().z(), 1.5, 0.05);
  EXPECT_NEAR(on_deck.length, 6.1, 0.05);  // cell centres -3.05 to 3.05
  const PatchPath on_road = plan_on_patches(graph, {5.05, 0.05, 0.0}, {.x = 0.05, .y = 0.05});
  ASSERT_TRUE(on_road.found()) << describe(on_road.status);
  EXPECT_NEAR(on_road.points.back().z(), 0.0, 0.05);
}

TEST(PatchGraphPlanner, PathsAreOptimalWithStraightAndDiagonalSteps) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath path = plan_on_patches(graph, {-1.95, -1.95, 0.0}, {.x = 1.05, .y = 0.05});
  ASSERT_TRUE(path.found()) << describe(path.status);
  // 30 cells east and 20 north: 10 straight and 20 diagonal steps.
  EXPECT_NEAR(path.length, 0.1 * (10.0 + 20.0 * std::sqrt(2.0)), 1e-6);
}

TEST(PatchGraphPlanner, GoalInAWallIsUnreachable) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath in_wall = plan_on_patches(graph, {0, 0, 0}, {.x = -2.99, .y = 0.05});
  EXPECT_EQ(in_wall.status, PatchPlanStatus::goal_blocked);
  const PatchPath beside_wall = plan_on_patches(graph, {0, 0, 0}, {.x = -2.85, .y = 0.05});
  EXPECT_EQ(beside_wall.status, PatchPlanStatus::goal_blocked);  // no room for the robot
  const PatchPath behind_wall = plan_on_patches(graph, {0, 0, 0}, {.x = -4.5, .y = 0.05});
  EXPECT_FALSE(behind_wall.found());
}

TEST(PatchGraphPlanner, AGoalBesideAWallMovesAlongItsFloorToTheNearestPlaceWithRoom) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath beside_wall =
      plan_on_patches(graph, {0, 0, 0}, {.x = -2.85, .y = 0.05, .room_search_radius = 0.5});
  ASSERT_TRUE(beside_wall.found()) << describe(beside_wall.status);
  ASSERT_TRUE(beside_wall.moved_goal.has_value());
  const Eigen::Vector3d moved = *beside_wall.moved_goal;
  EXPECT_GT(moved.x(), -2.85);  // away from the wall at x = -3
  EXPECT_LE(std::hypot(moved.x() + 2.85, moved.y() - 0.05), 0.5);
  EXPECT_NEAR(moved.z(), 0.0, 0.05);
  EXPECT_EQ(beside_wall.points.back(), moved);  // the path ends there
  const auto end = graph.locate(moved.x(), moved.y(), moved.z(), 0.1);
  ASSERT_TRUE(end.has_value());
  EXPECT_TRUE(graph.passable(*end));
  // A goal with room is not moved; one in the wall or on a step is still refused.
  EXPECT_FALSE(plan_on_patches(graph, {0, 0, 0}, {.x = 1.05, .y = 0.05, .room_search_radius = 0.5})
                   .moved_goal.has_value());
  EXPECT_EQ(plan_on_patches(graph, {0, 0, 0}, {.x = -2.99, .y = 0.05, .room_search_radius = 0.5}).status,
            PatchPlanStatus::goal_blocked);
  EXPECT_EQ(
      plan_on_patches(graph, {0, 0, 0}, {.x = 2.45, .y = 0.05, .z = 0.3, .room_search_radius = 0.5}).status,
      PatchPlanStatus::goal_blocked);
  // Further than the radius from any place with room: refused.
  EXPECT_EQ(plan_on_patches(graph, {0, 0, 0}, {.x = -2.85, .y = 0.05, .room_search_radius = 0.05}).status,
            PatchPlanStatus::goal_blocked);
}

TEST(PatchGraphPlanner, StairsAreUnreachable) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath on_step = plan_on_patches(graph, {0, 0, 0}, {.x = 2.45, .y = 0.05, .z = 0.3});
  EXPECT_EQ(on_step.status, PatchPlanStatus::goal_blocked);
  const PatchPath on_landing = plan_on_patches(graph, {0, 0, 0}, {.x = 4.05, .y = 0.05, .z = 0.45});
  EXPECT_EQ(on_landing.status, PatchPlanStatus::no_path);
}

TEST(PatchGraphPlanner, OffTheMapAndBadHeightsAreReported) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  EXPECT_EQ(plan_on_patches(graph, {0, 0, 0}, {.x = 40, .y = 0}).status, PatchPlanStatus::goal_off_map);
  EXPECT_EQ(plan_on_patches(graph, {40, 0, 0}, {.x = 0, .y = 0}).status, PatchPlanStatus::start_off_map);
  EXPECT_EQ(plan_on_patches(graph, {0, 0, 0}, {.x = 1, .y = 0, .z = 5.0}).status,
            PatchPlanStatus::goal_blocked);
}

TEST(PatchGraphPlanner, ARobotTooNearAnEdgeDrivesAwayFromIt) {
  const MlsMap map = test::wall_and_stairs_scene();
  const PatchGraph graph = test::graph_of(map);
  const PatchPath path = plan_on_patches(graph, {-2.85, 0.05, 0}, {.x = 0.05, .y = 0.05});
  ASSERT_TRUE(path.found()) << describe(path.status);
  EXPECT_NEAR(path.length, 2.9, 1e-6);
}

}  // namespace
}  // namespace strata

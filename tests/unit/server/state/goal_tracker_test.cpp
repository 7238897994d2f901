#include "server/state/goal_tracker.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

TEST(GoalTracker, GoesThroughPlanningAndDrivingToReached) {
  GoalTracker tracker;
  EXPECT_FALSE(tracker.active());
  EXPECT_EQ(tracker.status().id, 0U);
  const auto id = tracker.accept({1.0, 2.0, {}}, 0.5);
  EXPECT_EQ(tracker.status().phase, GoalPhase::kAccepted);
  EXPECT_TRUE(tracker.active());
  EXPECT_TRUE(tracker.planning(id, 1.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kPlanning);
  EXPECT_TRUE(tracker.driving(id, 2.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kDriving);
  EXPECT_TRUE(tracker.reached(id, 3.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kReached);
  EXPECT_EQ(tracker.status().stamp, 3.0);
  EXPECT_FALSE(tracker.active());
}

TEST(GoalTracker, RefusesTransitionsOutOfOrder) {
  GoalTracker tracker;
  const auto id = tracker.accept({1.0, 2.0, {}}, 0.0);
  EXPECT_FALSE(tracker.driving(id, 1.0));  // not planned yet
  EXPECT_FALSE(tracker.reached(id, 1.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kAccepted);
  EXPECT_TRUE(tracker.fail(id, "no_connection", "no drivable connection to the goal", 1.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kFailed);
  EXPECT_EQ(tracker.status().reason, "no_connection");
  EXPECT_EQ(tracker.status().message, "no drivable connection to the goal");
  EXPECT_FALSE(tracker.planning(id, 2.0));  // failed is final
  EXPECT_FALSE(tracker.cancel(2.0));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kFailed);
}

TEST(GoalTracker, ANewGoalReplacesTheOldOne) {
  GoalTracker tracker;
  const auto first = tracker.accept({1.0, 2.0, {}}, 0.0);
  ASSERT_TRUE(tracker.planning(first, 0.1));
  const auto second = tracker.accept({5.0, 6.0, 3.0}, 0.2);
  EXPECT_NE(first, second);
  EXPECT_EQ(tracker.status().id, second);
  EXPECT_EQ(tracker.status().phase, GoalPhase::kAccepted);
  ASSERT_TRUE(tracker.status().target.z.has_value());
  EXPECT_EQ(*tracker.status().target.z, 3.0);
  // A late answer for the replaced goal changes nothing.
  EXPECT_FALSE(tracker.driving(first, 0.3));
  EXPECT_FALSE(tracker.fail(first, "no_connection", "no drivable connection to the goal", 0.3));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kAccepted);
}

TEST(GoalTracker, CancelEndsTheActiveGoal) {
  GoalTracker tracker;
  const auto id = tracker.accept({1.0, 2.0, {}}, 0.0);
  ASSERT_TRUE(tracker.planning(id, 0.1));
  ASSERT_TRUE(tracker.driving(id, 0.2));
  EXPECT_TRUE(tracker.cancel(0.3));
  EXPECT_EQ(tracker.status().phase, GoalPhase::kCancelled);
  EXPECT_FALSE(tracker.reached(id, 0.4));
  EXPECT_FALSE(tracker.cancel(0.5));  // nothing left to cancel
}

}  // namespace
}  // namespace strata

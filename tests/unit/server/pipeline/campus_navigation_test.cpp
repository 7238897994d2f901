// The navigator driving the simulated robot on the campus (drivers/sim/worlds/campus.json): the
// simulator is stepped in-process without a wall clock and the robot is localized by its true pose, so
// every run is the same. The map is a survey of the world (tests/support/world_survey.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>

#include "core/mls/drivable_map.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/navigator.hpp"
#include "tests/support/world_survey.hpp"

namespace strata {
namespace {

struct Area {
  double x0, y0, x1, y1;
};

/// The campus with the robot put down at (x, y) facing `yaw_deg`, on the surface just below z + 0.5.
std::shared_ptr<const sim::World> campus_with_spawn(double x, double y, double z, double yaw_deg) {
  sim::WorldDescription description = sim::builtin_world("campus");
  description.spawn = {x, y, yaw_deg * std::numbers::pi / 180.0};
  description.spawn_z = z;
  return std::make_shared<const sim::World>(std::move(description));
}

/// One simulated trip: a robot, a map of `area`, and a navigator that the test drives step by step.
class Trip {
 public:
  Trip(std::shared_ptr<const sim::World> world, const Area& area,
       sim::ScannerKind scanner = sim::ScannerKind::kNone)
      : world_(std::move(world)),
        map_(test::survey_world(*world_, area.x0, area.y0, area.x1, area.y1)),
        simulator_(world_, config(scanner)) {
    const DrivableMap drivable;
    navigator_.on_map_update({map_, drivable, simulator_.sample().truth->position, map_.version()});
    step();  // the navigator learns where the robot is
  }

  static sim::SimulatorConfig config(sim::ScannerKind scanner) {
    sim::SimulatorConfig config;
    config.scanner = scanner;
    config.tilting.rotation_step_deg = 6.0;  // a coarse tilting scan: the stops are what matters here
    config.tilting.slice_step_deg = 3.0;
    return config;
  }

  /// One step of 0.1 s: the navigator's command, the simulator, then any pending plan.
  void step() {
    const RobotSample sample = simulator_.sample();
    if (const auto command = navigator_.drive(*sample.truth, sample.stamp))
      simulator_.command({command->v, command->w});
    simulator_.step(kStep);
    if (std::getenv("STRATA_TRACE") && ++steps_ % 10 == 0) {
      const auto s = simulator_.sample();
      std::printf("t %.1f pose %.2f %.2f %.2f yaw %.2f v %.2f w %.2f blocked '%s' phase %s %s\n", s.stamp,
                  s.truth->position.x(), s.truth->position.y(), s.truth->position.z(), s.truth->yaw,
                  s.velocity.v, s.velocity.w, s.blocked_by.c_str(), to_string(navigator_.goal_status().phase),
                  navigator_.goal_status().reason.c_str());
    }
    scanned_ = scanned_ || simulator_.sample().scanning;
    for (const ScanEvent& scan : simulator_.take_scans())
      map_scan(scan);
    navigator_.plan_pending();
    if (const auto path = navigator_.path())
      latest_path_version_ = std::max(latest_path_version_, path->version);
  }

  /// Steps until the goal is no longer active or `seconds` of simulated time have passed.
  GoalStatus drive_to(const GoalRequest& goal, double seconds) {
    EXPECT_TRUE(navigator_.set_goal(goal).ok);
    navigator_.plan_pending();
    for (double t = 0.0; t < seconds; t += kStep) {
      const GoalPhase phase = navigator_.goal_status().phase;
      if (phase != GoalPhase::kAccepted && phase != GoalPhase::kPlanning && phase != GoalPhase::kDriving)
        break;
      step();
    }
    return navigator_.goal_status();
  }

  /// Maps a scan at its true pose and hands the map to the navigator, as the mapping worker does.
  void map_scan(const ScanEvent& scan) {
    const Eigen::Isometry3d map_from_sensor = scan.truth->to_isometry() * scan.sensor_to_base;
    PointCloud points;
    for (const Eigen::Vector3f& p : scan.points)
      if (scan.max_range <= 0.0 || p.cast<double>().norm() < scan.max_range - 1e-3)
        points.push_back(map_from_sensor * p.cast<double>());
    map_.insert_scan(points, map_from_sensor.translation());
    const DrivableMap drivable;
    navigator_.on_map_update({map_, drivable, scan.truth->position, map_.version()});
    ++scans_mapped_;
  }
  [[nodiscard]] int scans_mapped() const { return scans_mapped_; }
  [[nodiscard]] std::uint64_t latest_path_version() const { return latest_path_version_; }

  [[nodiscard]] Pose3 truth() const { return *simulator_.sample().truth; }
  [[nodiscard]] double distance_to(double x, double y) const {
    return std::hypot(truth().position.x() - x, truth().position.y() - y);
  }
  pipeline::Navigator& navigator() { return navigator_; }
  sim::Simulator& simulator() { return simulator_; }
  [[nodiscard]] bool scanned() const { return scanned_; }

  static constexpr double kStep = 0.1;

 private:
  std::shared_ptr<const sim::World> world_;
  MlsMap map_;
  sim::Simulator simulator_;
  pipeline::Navigator navigator_;
  bool scanned_ = false;
  int steps_ = 0;
  int scans_mapped_ = 0;
  std::uint64_t latest_path_version_ = 0;
};

TEST(CampusNavigation, GoalDownTheHallwayIsReached) {
  // From the lab (the world's spawn) out through its door and east along the hallway.
  Trip trip(campus_with_spawn(4.0, 9.5, 0.45, 0.0), {-1, -1, 23, 13});
  const GoalStatus status = trip.drive_to({20.0, 5.25, {}}, 200.0);
  EXPECT_EQ(status.phase, GoalPhase::kReached) << to_string(status.phase) << " " << status.reason;
  EXPECT_LT(trip.distance_to(20.0, 5.25), 0.3);
  EXPECT_NEAR(trip.truth().position.z(), 0.45, 0.05);
}

TEST(CampusNavigation, StopAndGoScansOnTheWay) {
  Trip trip(campus_with_spawn(20.0, 5.25, 0.45, 0.0), {14, 3, 35, 7}, sim::ScannerKind::kTilting);
  const GoalStatus status = trip.drive_to({28.0, 5.25, {}}, 120.0);
  EXPECT_EQ(status.phase, GoalPhase::kReached) << to_string(status.phase) << " " << status.reason;
  EXPECT_LT(trip.distance_to(28.0, 5.25), 0.3);
  EXPECT_TRUE(trip.scanned());  // stopped to scan along the 8 m, and each scan updated the map and the plan
  EXPECT_GE(trip.scans_mapped(), 2);
  EXPECT_GE(trip.latest_path_version(), 2U);  // replanned on a new map
}

TEST(CampusNavigation, GoalUpTheEntranceRampIsReached) {
  // From the campus up the 1:12 ramp onto the landing and into the hallway.
  Trip trip(campus_with_spawn(57.0, 2.0, 0.0, 180.0), {42, -1, 60, 10});
  const GoalStatus status = trip.drive_to({44.0, 5.25, {}}, 200.0);
  EXPECT_EQ(status.phase, GoalPhase::kReached) << to_string(status.phase) << " " << status.reason;
  EXPECT_LT(trip.distance_to(44.0, 5.25), 0.3);
  EXPECT_NEAR(trip.truth().position.z(), 0.45, 0.05);
}

TEST(CampusNavigation, GoalOnTheBridgeDeckIsReachedOverTheRamp) {
  Trip trip(campus_with_spawn(44.0, -28.75, 0.0, 0.0), {40, -33, 84, -24});
  const GoalStatus status = trip.drive_to({80.0, -28.75, 3.0}, 300.0);
  EXPECT_EQ(status.phase, GoalPhase::kReached) << to_string(status.phase) << " " << status.reason;
  EXPECT_LT(trip.distance_to(80.0, -28.75), 0.3);
  EXPECT_NEAR(trip.truth().position.z(), 3.0, 0.1);  // on the deck, not on the road below
}

TEST(CampusNavigation, GoalOnTheRoadUnderTheBridgeIsReachedUnderIt) {
  Trip trip(campus_with_spawn(84.0, -18.0, 0.0, -90.0), {78, -38, 92, -14});
  const GoalStatus status = trip.drive_to({84.0, -36.0, 0.0}, 200.0);
  EXPECT_EQ(status.phase, GoalPhase::kReached) << to_string(status.phase) << " " << status.reason;
  EXPECT_LT(trip.distance_to(84.0, -36.0), 0.3);
  EXPECT_LT(trip.truth().position.z(), 0.3);
}

TEST(CampusNavigation, GoalsInAWallOrOnTheStairsAreNoPlaceForTheRobot) {
  Trip trip(campus_with_spawn(46.0, 5.25, 0.45, 0.0), {43, 2, 53, 10});
  const GoalStatus in_wall = trip.drive_to({44.0, 3.9, {}}, 5.0);  // hallway-wall-south
  EXPECT_EQ(in_wall.phase, GoalPhase::kFailed);
  EXPECT_EQ(in_wall.reason, "goal_not_drivable");
  // Where to go instead: the hallway floor beside the wall, as near as the robot's radius lets it.
  const std::string instead = "; the nearest place the robot can reach is (";
  const std::size_t at = in_wall.message.find(instead);
  ASSERT_NE(at, std::string::npos) << in_wall.message;
  double x = 0.0;
  double y = 0.0;
  ASSERT_EQ(std::sscanf(in_wall.message.c_str() + at + instead.size(), "%lf, %lf", &x, &y), 2);
  EXPECT_NEAR(x, 44.0, 0.3);
  EXPECT_GT(y, 4.0 + 0.45 - 0.05) << "the wall's face plus the robot's radius";
  EXPECT_LT(y, 4.8);
  const GoalStatus on_stairs = trip.drive_to({50.05, 7.5, {}}, 5.0);  // the middle step
  EXPECT_EQ(on_stairs.phase, GoalPhase::kFailed);
  EXPECT_EQ(on_stairs.reason, "goal_not_drivable");
  EXPECT_LT(trip.distance_to(46.0, 5.25), 0.05);  // the robot never moved
  // The top step, at the landing's height, is the landing's own edge above the stairs: ground without room
  // for the robot. The goal moves back along it onto the landing (within 0.5 m) and the robot stops there,
  // short of the stairs.
  const GoalStatus top_step = trip.drive_to({49.7, 7.5, 0.45}, 60.0);
  EXPECT_EQ(top_step.phase, GoalPhase::kReached) << to_string(top_step.phase) << " " << top_step.message;
  EXPECT_NE(top_step.message.find("driving to the nearest place with room"), std::string::npos)
      << top_step.message;
  EXPECT_LT(trip.truth().position.x(), 49.7 - 0.1);
  EXPECT_GT(trip.truth().position.x(), 49.7 - 0.8);
  EXPECT_NEAR(trip.truth().position.z(), 0.45, 0.1);
}

TEST(CampusNavigation, CancelStopsTheRobot) {
  Trip trip(campus_with_spawn(20.0, 5.25, 0.45, 0.0), {14, 3, 40, 7});
  ASSERT_TRUE(trip.navigator().set_goal({36.0, 5.25, {}}).ok);
  for (int i = 0; i < 50; ++i)  // 5 s: under way
    trip.step();
  ASSERT_EQ(trip.navigator().goal_status().phase, GoalPhase::kDriving);
  ASSERT_GT(trip.simulator().sample().velocity.v, 0.3);
  ASSERT_TRUE(trip.navigator().cancel_goal().ok);
  for (int i = 0; i < 20; ++i)  // 2 s: enough to brake from cruising speed
    trip.step();
  EXPECT_EQ(trip.navigator().goal_status().phase, GoalPhase::kCancelled);
  EXPECT_EQ(trip.simulator().sample().velocity.v, 0.0);
  const double x = trip.truth().position.x();
  for (int i = 0; i < 20; ++i)
    trip.step();
  EXPECT_EQ(trip.truth().position.x(), x);  // and stays
  EXPECT_LT(x, 36.0 - 5.0);
}

}  // namespace
}  // namespace strata

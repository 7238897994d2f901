// The core localizer over simulated runs: the state it reports is the estimate's. Loop closures confirm
// the estimate; a place a search found is taken for good only when the scans after it match there.
#include "core/localization/localizer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>

#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "tests/support/sim_saved_map.hpp"

namespace strata {
namespace {

ScanToLocalize to_localize(const ScanEvent& scan) {
  ScanToLocalize in;
  in.points = pipeline::points_in_base(scan);
  in.stamp = scan.stamp;
  in.odometry = Pose2{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw};
  return in;
}

/// The robot's simulated run (stop-and-go scanner, a quarter of the rays: quick under ASan), its
/// localizer started where it truly is.
struct SimulatedRun {
  explicit SimulatedRun(const std::string& world, std::uint64_t seed = 1,
                        LocalizationHealthOptions health = {})
      : simulator(std::make_shared<const sim::World>(sim::builtin_world(world)),
                  {.seed = seed, .tilting = {.slice_step_deg = 2.0, .rotation_step_deg = 2.0}}),
        localizer(
            GraphLocalizerOptions{},
            simulator.sample().truth->to_isometry() * simulator.sample().odometry.to_isometry().inverse(),
            health) {}

  /// The next scan through the localizer (the loop search after it, as the server's thread runs it).
  LocalizedScan next_scan() {
    while (true) {
      simulator.step(0.02);
      for (const ScanEvent& event : simulator.take_scans()) {
        truth = *event.truth;
        ScanToLocalize scan = to_localize(event);
        LocalizedScan localized = localizer.localize(scan);
        localizer.close_loops();
        return localized;
      }
    }
  }
  [[nodiscard]] double error(const LocalizedScan& localized) const {
    return (localized.pose.translation() - truth.position).head<2>().norm();
  }

  sim::Simulator simulator;
  Localizer localizer;
  Pose3 truth;
};

// The yard's straight sides are corridors to the tilting scanner: the position along them is odometry's.
// With the stretch that makes it degraded cut to 5 m (the sides are 9 m), the first lap is degraded along
// its sides. From the first loop closure on, each loop confirms the estimate against the map of the lap
// before, and the second lap, along the same sides, stays ok: without the loops it was degraded along them
// as the first.
TEST(Localizer, ADegradedStretchClearsWhenALoopIsClosed) {
  SimulatedRun run("yard", 1, {.degraded_odometry_distance = 5.0});
  bool degraded_before_the_loops = false;
  std::size_t scans_after_the_first_loop = 0;
  while (run.simulator.sample().stamp < 300.0) {
    const bool looped = run.localizer.graph_status().loops > 0;  // before this scan
    const LocalizedScan localized = run.next_scan();
    ASSERT_LT(run.error(localized), 0.15) << "the estimate itself stays good";
    if (!looped) {
      degraded_before_the_loops =
          degraded_before_the_loops || localized.health.state == LocalizationState::kDegraded;
      continue;
    }
    ++scans_after_the_first_loop;
    EXPECT_EQ(localized.health.state, LocalizationState::kOk)
        << "t=" << run.simulator.sample().stamp << ": " << localized.health.reason;
  }
  EXPECT_TRUE(degraded_before_the_loops);
  EXPECT_GE(scans_after_the_first_loop, 15U);
}

/// A second run (seed 2) of the yard localizing in the map of the first run's first 21 scans.
struct RunInYardMap : SimulatedRun {
  RunInYardMap() : SimulatedRun("yard", 2) {
    localizer.localize_in(std::make_shared<const LocalizationMap>(
        test::saved_map_of_run(std::make_shared<const sim::World>(sim::builtin_world("yard")), 21)));
  }
};

// An operator's estimate 5 m from where the robot is, each way along and across its heading: the search
// looks within 2 m of it, where the robot is not. Nothing outside that radius is taken, and nothing taken
// stays: within 5 scans the robot is where it truly is or no search found it; the state never says ok
// while the estimate is metres off.
TEST(Localizer, ASetPoseFiveMetresOffIsRefusedOrCorrectedWithinFiveScans) {
  for (const double angle : {0.0, 1.57, 3.14, -1.57}) {
    RunInYardMap run;
    for (int i = 0; i < 3; ++i)
      run.next_scan();
    const Pose3 now = run.truth;
    const PoseEstimate hint{.x = now.position.x() + 5.0 * std::cos(now.yaw + angle),
                            .y = now.position.y() + 5.0 * std::sin(now.yaw + angle),
                            .yaw = now.yaw};
    run.localizer.search_at_next_scan(hint);
    for (int scan = 1; scan <= 5; ++scan) {
      const LocalizedScan localized = run.next_scan();
      for (const RelocalizationReport& search : localized.searches) {
        if (search.search == RelocalizationReport::Search::kHint && search.found) {
          const double from_hint = std::hypot(localized.update.pose.translation().x() - hint.x,
                                              localized.update.pose.translation().y() - hint.y);
          EXPECT_LE(from_hint, 2.25) << "taken outside the radius searched: " << search.message;
        }
      }
      if (localized.health.state == LocalizationState::kOk || scan == 5) {
        EXPECT_LT(run.error(localized), 0.3)
            << "scan " << scan << " after the estimate, at " << angle << ": " << localized.health.reason;
      }
    }
  }
}

}  // namespace
}  // namespace strata

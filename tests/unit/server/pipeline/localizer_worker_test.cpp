#include "server/pipeline/localizer_worker.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <vector>

#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "tests/support/sim_saved_map.hpp"

namespace strata::pipeline {
namespace {

// A robot that believes it starts 5.7 m from where it does, in a saved map of the yard: its scans cannot
// register (the jump limit is 1 m), it is lost after ten of them, and then it is searched for over the whole
// map: the first search is refused (the yard's mirror image 14 m away fits 97 % to its 100 %), the one five
// scans later finds it; from there its scans register where it is.
TEST(LocalizerWorker, ARobotLostInASavedMapIsFoundAgain) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  auto saved = std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 21));
  sim::Simulator run(world, {.seed = 2});
  Eigen::Isometry3d wrong = Eigen::Isometry3d::Identity();
  wrong.translation() = Eigen::Vector3d(4.0, -4.0, 0.0);
  const Eigen::Isometry3d believed =
      wrong * run.sample().truth->to_isometry() * run.sample().odometry.to_isometry().inverse();
  RobotState state;
  LocalizerWorker worker(state, GraphLocalizerOptions{}, believed);
  std::optional<double> last_error;
  worker.set_registered_scan_sink([&](PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor) {
    const Eigen::Isometry3d truth = scan.event.truth->to_isometry() * scan.event.sensor_to_base;
    last_error = (map_from_sensor.translation() - truth.translation()).norm();
  });
  EXPECT_FALSE(worker.set_pose_estimate({.x = 0.0, .y = 0.0, .yaw = 0.0, .z = std::nullopt}).ok)
      << "no map to search yet";
  worker.localize_in(saved);
  worker.start();
  bool found = false;
  std::size_t scans = 0;
  while (scans < 40 && !(found && last_error)) {
    run.step(0.01);
    for (ScanEvent& scan : run.take_scans()) {
      worker.submit(std::move(scan));
      ASSERT_TRUE(worker.flush());
      ++scans;
      const RegistrationStatus status = state.registration();
      if (status.relocalization && status.relocalization->found && !found) {
        found = true;
        EXPECT_EQ(status.localization.state, LocalizationState::kLost) << "searched only once lost";
        last_error.reset();  // from the next scan on
      }
    }
  }
  worker.stop();
  ASSERT_TRUE(found) << "never found in " << scans
                     << " scans: " << state.registration().relocalization->message;
  ASSERT_TRUE(last_error) << "no scan registered after it was found";
  EXPECT_LT(*last_error, 0.2);
}

}  // namespace
}  // namespace strata::pipeline

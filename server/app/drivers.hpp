#pragma once

#include <memory>

#include "drivers/robot_driver.hpp"
#include "server/app/serve.hpp"

namespace strata::app {

/// The driver `strata serve` runs: a lidar capture (--pcap FILE --lidar MODEL) or the live lidar (--lidar
/// MODEL), a replay of --replay DIR, else the simulated robot in --world. Throws with a clear message when
/// the world, the dataset, the capture or the lidar's calibration cannot be used, or the lidar's port cannot
/// be bound.
[[nodiscard]] std::unique_ptr<RobotDriver> make_driver(const ServeOptions& options);

}  // namespace strata::app

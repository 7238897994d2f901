#pragma once

#include <memory>

#include "drivers/robot_driver.hpp"
#include "server/app/serve.hpp"

namespace strata::app {

/// The driver `strata serve` runs: a replay of --replay DIR, else the simulated robot in --world. Throws
/// with a clear message when the world or the dataset cannot be used.
[[nodiscard]] std::unique_ptr<RobotDriver> make_driver(const ServeOptions& options);

}  // namespace strata::app

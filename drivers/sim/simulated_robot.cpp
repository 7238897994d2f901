#include "drivers/sim/simulated_robot.hpp"

#include <chrono>
#include <stdexcept>
#include <utility>

namespace strata::sim {

SimulatedRobot::SimulatedRobot(Simulator simulator, SimulatedRobotConfig config, SampleCallback on_sample,
                               ScanCallback on_scan)
    : simulator_(std::move(simulator)),
      config_(config),
      on_sample_(std::move(on_sample)),
      on_scan_(std::move(on_scan)) {
  if (!(config_.step_rate > 0.0) || !(config_.time_scale > 0.0)) {
    throw std::invalid_argument("simulator step rate and time scale must be positive");
  }
}

SimulatedRobot::~SimulatedRobot() {
  stop();
}

void SimulatedRobot::start() {
  if (running_.exchange(true))
    return;
  on_sample_(simulator_.sample());
  thread_ = std::thread([this] { run(); });
}

void SimulatedRobot::stop() {
  running_ = false;
  if (thread_.joinable())
    thread_.join();
}

void SimulatedRobot::run() {
  using clock = std::chrono::steady_clock;
  const double dt = 1.0 / config_.step_rate;
  const auto wall_period =
      std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(dt / config_.time_scale));
  auto next = clock::now();
  while (running_) {
    if (command_source_) {
      if (const auto command = command_source_(simulator_.sample()))
        simulator_.command(*command);
    }
    simulator_.step(dt);
    on_sample_(simulator_.sample());
    for (ScanEvent& scan : simulator_.take_scans()) {
      if (on_scan_)
        on_scan_(std::move(scan));
    }
    // Pace on an absolute schedule so the simulated clock does not drift from the wall clock;
    // if we fall behind (a slow machine, a debugger), skip ahead instead of bursting.
    next += wall_period;
    const auto now = clock::now();
    if (next < now - std::chrono::milliseconds(100))
      next = now;
    std::this_thread::sleep_until(next);
  }
}

}  // namespace strata::sim

#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "drivers/sim/simulator.hpp"

namespace strata::sim {

struct SimulatedRobotConfig {
  double step_rate = 100.0;  ///< simulated steps per simulated second
  double time_scale = 1.0;   ///< simulated seconds per wall-clock second (>1 runs faster than real time)
};

/// Runs a Simulator on its own thread, paced against the wall clock, and hands every new sample and
/// every completed scan to callbacks on that thread. This is the simulator's driver thread.
class SimulatedRobot {
 public:
  using SampleCallback = std::function<void(const RobotSample&)>;
  using ScanCallback = std::function<void(ScanEvent)>;
  /// Asked before every step with the latest sample: a (v, w) command for the base, or nothing to leave
  /// the simulator as it is (the demo route, or the last command). A controller such as the navigator.
  using CommandSource = std::function<std::optional<VelocityCommand>(const RobotSample&)>;

  SimulatedRobot(Simulator simulator, SimulatedRobotConfig config, SampleCallback on_sample,
                 ScanCallback on_scan = {});
  ~SimulatedRobot();
  SimulatedRobot(const SimulatedRobot&) = delete;
  SimulatedRobot& operator=(const SimulatedRobot&) = delete;

  /// Set before start(): called on the simulator's thread.
  void set_command_source(CommandSource source) { command_source_ = std::move(source); }
  void start();
  void stop();
  [[nodiscard]] const World& world() const { return simulator_.world(); }

 private:
  void run();

  Simulator simulator_;
  SimulatedRobotConfig config_;
  SampleCallback on_sample_;
  ScanCallback on_scan_;
  CommandSource command_source_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace strata::sim

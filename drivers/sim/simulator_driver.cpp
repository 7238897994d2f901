#include "drivers/sim/simulator_driver.hpp"

#include <string>
#include <utility>

namespace strata::sim {

SimulatorDriver::SimulatorDriver(Simulator simulator, SimulatedRobotConfig config, std::string description)
    : simulator_(std::move(simulator)), config_(config), description_(std::move(description)) {
  // The simulator holds its world by shared_ptr: the World stays where it is when the simulator moves
  // into the robot at start(), and lives as long as this driver.
  world_ = &simulator_->world();
  if (simulator_->config().imu)
    imu_name_ = "simulated IMU, seed " + std::to_string(simulator_->config().seed);
  const RobotSample start = simulator_->sample();
  initial_map_from_odom_ = start.truth->to_isometry() * start.odometry.to_isometry().inverse();
}

SimulatorDriver::~SimulatorDriver() {
  stop();
}

void SimulatorDriver::start(Outputs outputs) {
  if (robot_ || !simulator_)
    return;
  robot_ = std::make_unique<SimulatedRobot>(std::move(*simulator_), config_, std::move(outputs.on_sample),
                                            std::move(outputs.on_scan));
  simulator_.reset();
  if (command_source_)
    robot_->set_command_source(std::move(command_source_));
  robot_->start();
}

void SimulatorDriver::stop() {
  if (robot_)
    robot_->stop();
}

}  // namespace strata::sim

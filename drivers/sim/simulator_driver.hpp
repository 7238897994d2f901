#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "drivers/robot_driver.hpp"
#include "drivers/sim/simulated_robot.hpp"

namespace strata::sim {

/// The simulated robot behind the RobotDriver seam: a SimulatedRobot made at start() (it takes its
/// callbacks at construction), driving the world's demo route until the command source takes over.
class SimulatorDriver final : public RobotDriver {
 public:
  /// `description` is the log line ("world 'campus', tilting scanner, seed 1").
  SimulatorDriver(Simulator simulator, SimulatedRobotConfig config, std::string description);
  ~SimulatorDriver() override;

  [[nodiscard]] std::string kind() const override { return "simulator"; }
  [[nodiscard]] std::string description() const override { return description_; }
  /// The robot is told where it starts (as an operator sets an initial pose): the map frame is the world's.
  [[nodiscard]] Eigen::Isometry3d initial_map_from_odom() const override { return initial_map_from_odom_; }
  /// The simulated IMU draws its errors from the seed: one seed, one robot.
  [[nodiscard]] std::optional<std::string> imu_name() const override { return imu_name_; }
  [[nodiscard]] const World* world() const override { return world_; }
  [[nodiscard]] bool accepts_commands() const override { return true; }
  void set_command_source(CommandSource source) override { command_source_ = std::move(source); }
  void start(Outputs outputs) override;
  void stop() override;

 private:
  const World* world_ = nullptr;
  std::optional<Simulator> simulator_;  // until start() hands it to the robot
  SimulatedRobotConfig config_;
  std::string description_;
  std::optional<std::string> imu_name_;
  Eigen::Isometry3d initial_map_from_odom_;
  CommandSource command_source_;
  std::unique_ptr<SimulatedRobot> robot_;
};

}  // namespace strata::sim

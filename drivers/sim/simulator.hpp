#pragma once

#include <cstdint>

#include "core/geometry/pose.hpp"
#include "drivers/sim/diff_drive_base.hpp"
#include "drivers/sim/loop_driver.hpp"
#include "drivers/sim/wheel_odometry.hpp"
#include "drivers/sim/world.hpp"

namespace strata::sim {

struct SimulatorConfig {
  std::uint64_t seed = 1;
  DiffDriveLimits base;
  OdometryNoise odometry;
  Pose2 start{2.0, -3.5, 0.0};
};

/// What the robot knows and what is true at one instant of simulated time.
struct RobotSample {
  double stamp = 0.0;  ///< simulated seconds since the start
  Pose3 odometry;      ///< what the wheels report: drifts
  Pose3 truth;         ///< the ground truth, for display and evaluation only
  VelocityCommand velocity;
  bool bumped = false;  ///< the last step was blocked by an obstacle
};

/// The simulated robot in its world, advanced in fixed steps of simulated time. Pure and
/// single-threaded: the same seed and the same steps give the same samples.
class Simulator {
 public:
  Simulator(World world, LoopDriver driver, SimulatorConfig config);
  /// The default demo: the yard world, driving its loop.
  [[nodiscard]] static Simulator yard(SimulatorConfig config = {});

  void step(double dt);
  [[nodiscard]] RobotSample sample() const;
  [[nodiscard]] const World& world() const { return world_; }
  [[nodiscard]] const DiffDriveBase& base() const { return base_; }

 private:
  World world_;
  LoopDriver driver_;
  DiffDriveBase base_;
  WheelOdometry odometry_;
  double time_ = 0.0;
  bool bumped_ = false;
};

}  // namespace strata::sim

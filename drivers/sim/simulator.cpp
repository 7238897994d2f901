#include "drivers/sim/simulator.hpp"

#include <utility>

namespace strata::sim {

Simulator::Simulator(World world, LoopDriver driver, SimulatorConfig config)
    : world_(std::move(world)),
      driver_(std::move(driver)),
      base_(config.base, config.start),
      odometry_(config.base.wheel_separation, config.odometry, config.seed, config.start) {}

Simulator Simulator::yard(SimulatorConfig config) {
  return Simulator(World::yard(), LoopDriver::yard_loop(), config);
}

void Simulator::step(double dt) {
  const VelocityCommand command = driver_.command(base_.pose());
  const DiffDriveBase::Step next = base_.preview(command, dt);
  const DiffDriveLimits& limits = base_.limits();
  bumped_ = world_.collides(next.pose.x, next.pose.y, limits.radius, limits.height);
  if (bumped_) {
    base_.halt();  // a bumper stop: wheels do not turn, odometry sees nothing
  } else {
    base_.apply(next);
    odometry_.integrate(next.wheels);
  }
  time_ += dt;
}

RobotSample Simulator::sample() const {
  const Pose2& truth = base_.pose();
  RobotSample sample;
  sample.stamp = time_;
  sample.truth = Pose3::from_pose2(truth, world_.ground_height(truth.x, truth.y));
  sample.odometry = Pose3::from_pose2(odometry_.pose());
  sample.velocity = base_.velocity();
  sample.bumped = bumped_;
  return sample;
}

}  // namespace strata::sim

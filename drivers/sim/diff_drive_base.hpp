#pragma once

#include "core/geometry/pose.hpp"
#include "drivers/robot_sample.hpp"

namespace strata::sim {

struct DiffDriveLimits {
  double max_speed = 1.0;         ///< m/s
  double max_turn_rate = 1.2;     ///< rad/s
  double max_accel = 0.8;         ///< m/s^2
  double max_turn_accel = 2.0;    ///< rad/s^2
  double wheel_separation = 0.6;  ///< m, between the two drive wheels (a wheelchair's)
  double radius = 0.45;           ///< m, footprint radius used for collisions
  double height = 1.3;            ///< m
};

/// How far each drive wheel rolled during one step: what wheel encoders measure.
struct WheelTravel {
  double left = 0.0;
  double right = 0.0;
};

/// The kinematics of a differential-drive base on the ground plane. It follows (v, w) commands within
/// speed and acceleration limits; the simulator decides whether a step is allowed (collisions).
class DiffDriveBase {
 public:
  explicit DiffDriveBase(DiffDriveLimits limits, Pose2 start = {});

  /// Proposes the pose after `dt` seconds under `command` without moving.
  struct Step {
    Pose2 pose;
    VelocityCommand velocity;  ///< the velocity actually reached (after limits)
    WheelTravel wheels;
  };
  [[nodiscard]] Step preview(const VelocityCommand& command, double dt) const;
  void apply(const Step& step);
  /// Stops at once, as after a bump: the base stays where it is.
  void halt();

  [[nodiscard]] const Pose2& pose() const { return pose_; }
  [[nodiscard]] const VelocityCommand& velocity() const { return velocity_; }
  [[nodiscard]] const DiffDriveLimits& limits() const { return limits_; }

 private:
  DiffDriveLimits limits_;
  Pose2 pose_;
  VelocityCommand velocity_;
};

}  // namespace strata::sim

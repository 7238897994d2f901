#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "core/geometry/pose.hpp"

namespace strata {

struct ConstantVelocityOptions {
  /// What the base can do at most, for the scans before a velocity is known: the guess may then be off
  /// by this much per second since the last scan. 20 m/s covers a car in town (the HDL-32E capture
  /// drives at 14.8 m/s); 2 rad/s a walking person's turn.
  double max_speed = 20.0;
  double max_turn_rate = 2.0;
  /// How fast the base can change that motion, for the scans after: the guess may be off by what this
  /// does over the time since the last scan (a dt^2 / 2). 5 m/s^2 is a car braking hard or a walker
  /// stopping; 4 rad/s^2 a walker turning into a side corridor. At 10 Hz that adds 2.5 cm and 1 degree
  /// to the fixed jump limits; at 1 Hz, 2.5 m and 115 degrees: a slow scan stream may turn a corner.
  double max_acceleration = 5.0;
  double max_angular_acceleration = 4.0;
};

/// How far a guess may be from the truth, beyond the fixed jump limits: before the first velocity,
/// anything the base can do in the time since the last scan; after, what a change of its motion can.
struct GuessUncertainty {
  double translation = 0.0;  ///< metres
  double rotation = 0.0;     ///< radians
  /// False before a velocity is known: the guess (no motion) then says nothing of where the scan is, and
  /// no direction ICP leaves weakly constrained is taken from it (a car's first scans on a straight road).
  bool motion_known = true;
};

/// Odometry for a base that has none (a lidar alone): the motion between the last two registered scans,
/// per second, carried on (KISS-ICP's constant velocity model), as a planar odometry pose that the
/// localizer composes like wheel odometry. So a moving sensor's next scan is guessed where it will be,
/// not where the last one was. Planar: a height or tilt change is left to registration.
class ConstantVelocityPrediction {
 public:
  explicit ConstantVelocityPrediction(ConstantVelocityOptions options = {}) : options_(options) {}

  /// The odometry pose for a scan at `stamp`: the last one moved on by the velocity.
  [[nodiscard]] Pose2 predict(double stamp) const;
  /// Where the base is at `stamp` in the frame of the poses update() was given: the last one moved on by
  /// the velocity. None before a velocity is known.
  [[nodiscard]] std::optional<Eigen::Isometry3d> predict_pose(double stamp) const;
  /// How far off the prediction for a scan at `stamp` may be (GuessUncertainty).
  [[nodiscard]] GuessUncertainty uncertainty(double stamp) const;
  /// Whether a velocity is known (two scans registered one after the other, the map not moved between).
  [[nodiscard]] bool knows_velocity() const { return velocity_.has_value(); }
  /// That velocity: per second, in the base frame (x forward, y left, theta the turn rate).
  [[nodiscard]] const std::optional<Pose2>& velocity() const { return velocity_; }
  /// The scan at `stamp`, predicted at `odometry`, was found at `pose` (map frame); `registered` false
  /// when the match was rejected (the pose is then the guess and says nothing of the velocity).
  /// `map_moved`: the map frame was moved since the last scan (a pose graph correction), so the two
  /// poses are not comparable.
  void update(double stamp, const Pose2& odometry, const Eigen::Isometry3d& pose, bool registered,
              bool map_moved);

 private:
  struct Scan {
    double stamp = 0.0;
    Pose2 odometry;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  };
  ConstantVelocityOptions options_;
  std::optional<Scan> last_;
  std::optional<Pose2> velocity_;  ///< per second, in the base frame (x forward, y left, theta)
};

}  // namespace strata

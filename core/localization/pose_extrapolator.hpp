#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <optional>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"

namespace strata {

/// The robot's pose between scans, for the live pose and the driving. The localizer's correction carries
/// the odometry into the map (map_from_odom * odometry): that knows x, y and heading. Height and tilt it
/// cannot know: the correction holds the tilt of the last scan's ground, and carried over a change of
/// slope (over a platform and down its far ramp) the estimate climbs where the robot descends. Where the
/// base reports gravity with its samples, the tilt is the reading's and the height follows the ground
/// under the odometry's way: the climb since the correction's scan is added to the height at that scan.
/// Without gravity the estimate is the carried odometry, as before. The readings are taken less the IMU's
/// mounting error the localizer has learnt (GravityLeveling::bias, the pose graph's estimate): a reading
/// tilted 0.14 degrees by its mounting tilted the live pose by as much, and its climb by 2.4 mm a metre.
class PoseExtrapolator {
 public:
  /// The base's sample, in time order (a stamp earlier than the last starts afresh: a replay restarted).
  void add_sample(double stamp, const Pose3& odometry, const std::optional<GravityReading>& gravity);
  /// The localizer's correction, computed from the scan taken at `scan_stamp`; none for a given start.
  void set_correction(const Eigen::Isometry3d& map_from_odom, std::optional<double> scan_stamp);
  /// The reading's mounting error, a rotation vector in the base frame (radians; GravityLeveling::bias):
  /// the samples from now on are taken without it.
  void set_mounting_error(const Eigen::Vector3d& mounting) { mounting_ = mounting; }
  /// A base without odometry (a lidar alone): its velocity from the last scans (per second, base frame;
  /// ConstantVelocityPrediction), which carries the last scan's pose on to the newest sample, for at most
  /// kMaxCarried seconds. Otherwise every pose between two scans would be the last scan's, behind the
  /// robot by its motion since. None: a base with odometry, or no velocity known yet.
  void set_velocity(const std::optional<Pose2>& velocity) { velocity_ = velocity; }
  static constexpr double kMaxCarried = 1.0;
  /// Where the robot is now; the odometry's origin before the first sample.
  [[nodiscard]] Pose3 estimate() const;

 private:
  struct Step {
    double stamp = 0.0;
    Pose3 odometry;
    double climb = 0.0;  ///< metres climbed along the odometry's way since the first sample kept
  };

  std::deque<Step> steps_;                 ///< from the correction's scan (or just before it) to now
  std::optional<GravityReading> gravity_;  ///< the newest sample's, when usable, less the mounting error
  Eigen::Vector3d mounting_ = Eigen::Vector3d::Zero();  ///< the readings' mounting error (set_mounting_error)
  Eigen::Isometry3d map_from_odom_ = Eigen::Isometry3d::Identity();
  std::optional<double> scan_stamp_;
  std::optional<Pose2> velocity_;
};

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "core/geometry/gravity.hpp"

namespace strata {

struct GravityLevelingOptions {
  /// How far scan matching's tilt walks per scan, radians (standard deviation).
  double drift_per_scan = 0.001;
  /// How fast the reading's own error (an accelerometer's mounting and calibration: a fixed tilt in the
  /// base frame) is learnt, per radian the base turns: what the readings disagree with scan matching by,
  /// on average over the last 1 / `bias_rate_per_radian` radians turned. Only turning tells the mounting
  /// error (fixed in the base) from scan matching's walk (fixed in the map); a rate per scan learnt the
  /// walk as mounting error on a 10 Hz lidar driving straight, and stopped levelling it (the height
  /// walked 1.6 m in 150 s).
  double bias_rate_per_radian = 0.13;
  /// How well the starting pose's tilt is known, radians. A start placed at a given pose (the
  /// simulator's spawn, a recording's initial pose) is sure of it, and the first readings teach the
  /// mounting error; a start at the odometry's origin on unknown ground is not, and takes them.
  double given_start_tilt_sigma = 0.002;
  double unknown_start_tilt_sigma = 0.1;
  /// How much the ground's tilt may change per metre driven, radians (standard deviation): onto a 6
  /// degree ramp within a metre. A scan's guess keeps the last scan's tilt and turns toward the reading
  /// by how much the tilt may have changed since against the reading's noise: a tilting scanner's scans
  /// metres apart take the reading (a ramp begun), a 10 Hz lidar's a tenth of a metre apart mostly keep
  /// the last tilt. Turned fully to each reading (0.01 rad of noise while driving), the lidar's guesses
  /// were tilted by the noise, which ICP against rings 5 m away and more corrects only in part: its height
  /// fell 0.15 m in its first two seconds on the campus (docs/benchmarks.md, "The guess's tilt").
  double tilt_change_per_metre = 0.1;
};

/// Levels the scan path's roll and pitch with gravity (docs/architecture.md 4.1, gravity). Scan matching
/// against a local map walks in tilt, a little with each scan, and a tilt error turns into height error
/// with every metre driven; gravity readings do not walk but are noisy, and tilted by the IMU's mounting
/// error. A Kalman filter on the tilt error weighs the two: its variance grows by `drift_per_scan`^2 with
/// each scan matched and shrinks with each reading, and the pose turns toward the reading by the filter's
/// gain. The mounting error is learnt as a tilt fixed in the base frame: scan matching's walk is fixed in
/// the map frame instead, so as the robot turns the two part. Heading is left alone (gravity cannot see
/// it).
class GravityLeveling {
 public:
  /// `start_given`: whether the starting pose's tilt is known (GravityLevelingOptions).
  explicit GravityLeveling(GravityLevelingOptions options = {}, bool start_given = false);

  /// Whether a reading can be used at all: a finite unit vector (to 1 %) with a positive, finite sigma.
  /// Anything else is ignored here and never reaches the pose graph.
  [[nodiscard]] static bool usable(const GravityReading& gravity);

  /// The reading without the mounting error `mounting` (a rotation vector in the base frame, radians:
  /// the one that takes the true up to where the reading has it); unchanged when it is not usable.
  [[nodiscard]] static GravityReading without_mounting(const GravityReading& gravity,
                                                       const Eigen::Vector3d& mounting);
  /// The reading without the learnt mounting error; unchanged when it is not usable.
  [[nodiscard]] GravityReading corrected(const GravityReading& gravity) const;

  /// The rotation (map frame, about the base's position) that turns `pose`'s tilt toward `gravity` by
  /// the filter's gain and leaves its heading (heading_of) where it was; updates the filter and the
  /// mounting error. Identity for a reading that is not a unit vector with a positive sigma.
  [[nodiscard]] Eigen::Matrix3d level(const Eigen::Isometry3d& pose, const GravityReading& gravity);

  /// The turn toward where `gravity` (corrected) puts `pose`'s up, heading kept, without touching the
  /// filter: a guess's tilt, which is the last scan's and stale on a ramp begun in the `moved` metres
  /// since. Weighed by tilt_change_per_metre against the reading's sigma; with nothing moved known (none),
  /// by how sure the filter is of the tilt: a start at a given pose took one reading's noise (0.5 degrees)
  /// as its tilt and then held it (docs/benchmarks.md, "Loops on the bridge deck").
  [[nodiscard]] Eigen::Matrix3d align(const Eigen::Isometry3d& pose, const GravityReading& gravity,
                                      std::optional<double> moved = std::nullopt) const;

  [[nodiscard]] double variance() const { return variance_; }
  /// The learnt mounting error, a rotation vector in the base frame (radians; z always 0).
  [[nodiscard]] const Eigen::Vector3d& bias() const { return bias_; }
  /// Takes an estimate of the mounting error from elsewhere (the pose graph's, from every keyframe's
  /// reading at once); learning per radian turned goes on from it.
  void set_bias(const Eigen::Vector3d& bias) { bias_ = {bias.x(), bias.y(), 0.0}; }

 private:
  GravityLevelingOptions options_;
  double variance_;                     ///< of the tilt error, rad^2
  std::optional<double> last_heading_;  ///< of the last pose levelled, radians
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
};

}  // namespace strata

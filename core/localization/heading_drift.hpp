#pragma once

#include <deque>
#include <optional>
#include <span>

#include "core/geometry/standing_gyro.hpp"

namespace strata {

struct HeadingDriftOptions {
  bool enabled = true;
  /// The stretch of motion the drift is fitted over, seconds: long, as the estimate's heading errors are
  /// tenths of a degree where the drift grows with time (a gyro's 10 degrees an hour: 1.7 degrees in 10
  /// minutes); short enough to follow a bias that wanders with temperature.
  double window = 1200.0;
  /// Less motion than this: no drift is fitted yet, seconds.
  double min_window = 300.0;
  /// A larger drift, rad/s, is not the odometry's (a map that turned under the robot): not taken. 1e-3 is
  /// 200 degrees an hour, twenty times a consumer gyro's bias after calibration.
  double max_rate = 1e-3;
  /// What the gyro read standing still (StandingGyro) is its bias, measured directly: where a base reports
  /// it, it replaces the fit once the mean over the stands is this sure, rad/s (3 degrees an hour: a
  /// consumer gyro's noise over some 27 of the tilting scanner's 4.8 s stands). Before the first loop the
  /// fit reads half the drift or less (walls hold the heading only in stretches); the gyro read standing
  /// took the campus's maximum error from 0.40 to 0.30 m over ten seeds (docs/benchmarks.md, "Gyro at
  /// rest").
  double standing_max_sigma = 1.5e-5;
  /// The stands the bias is averaged over, seconds of standing: the last hour's, to follow a bias that
  /// wanders with temperature.
  double standing_window = 3600.0;
};

/// Where a keyframe's heading was: what the odometry said (its turns summed since the start, radians, not
/// wrapped) after `seconds` of motion since the start, and where the optimized pose graph has it.
struct HeadingSample {
  double seconds = 0.0;
  double odometry_heading = 0.0;
  double estimated_heading = 0.0;
};

/// The odometry's heading drift, radians to add per second of motion: a gyro's bias, which walks the
/// heading wherever scan matching cannot measure it (partial scans over open ground take their heading
/// from odometry) until a loop closes. The slope, by least squares, of the graph's heading less the
/// odometry's over the samples of the last `window` seconds of motion: where walls held the scans' heading
/// (before any loop), and the loops' corrections spread along the way (after). None where the samples span
/// too little motion or the slope is no odometry's drift.
[[nodiscard]] std::optional<double> fit_heading_drift(std::span<const HeadingSample> samples,
                                                      const HeadingDriftOptions& options = {});

/// The odometry's heading drift from the gyro's bias as it reads standing still: the stands' mean rate
/// weighed by their sigmas, over the last `standing_window` seconds of standing.
class StandingGyroDrift {
 public:
  explicit StandingGyroDrift(HeadingDriftOptions options = {}) : options_(options) {}

  /// One stand. Ignored: a reading that is not finite or has no time or no sigma.
  void add(const StandingGyro& reading);
  /// Radians to add per second of motion (the bias, negated), once the mean is sure to
  /// `standing_max_sigma`; none before.
  [[nodiscard]] std::optional<double> drift() const;
  /// The mean's standard deviation, rad/s; infinite before any stand.
  [[nodiscard]] double sigma() const;

 private:
  HeadingDriftOptions options_;
  std::deque<StandingGyro> stands_;
  double seconds_ = 0.0;
  double weights_ = 0.0;         ///< the stands' 1 / sigma^2, summed
  double weighted_rates_ = 0.0;  ///< their rates weighed so, summed
};

}  // namespace strata

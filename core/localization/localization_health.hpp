#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/localization/scan_to_map_localizer.hpp"
#include "core/registration/fault_check.hpp"

namespace strata {

/// How far the pose can be trusted now (docs/architecture.md 4.1, "Localization state").
enum class LocalizationState {
  kOk,        ///< the last scans corrected the pose (whole, or all but a direction nothing constrains)
  kDegraded,  ///< odometry carries the pose more than it should (scans unmatched, a long partial stretch)
  kLost,      ///< no scan matched for long: odometry only, too far off for a match to be trusted
};
[[nodiscard]] std::string_view to_string(LocalizationState state);

/// The state with its reason in plain words, for people (no eigenvalues).
struct LocalizationHealth {
  LocalizationState state = LocalizationState::kDegraded;
  std::string reason;
  /// Before the first scan: nothing has confirmed the pose yet.
  [[nodiscard]] static LocalizationHealth no_scan_yet();
};

/// What one scan's localization did: what LocalizationHealthClassifier is fed.
struct ScanOutcome {
  double stamp = 0.0;  ///< robot time, s
  /// Where the scan put the robot, map frame, m: how far it moved between scans (a lidar alone has no
  /// odometry to measure it by).
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  bool registered = false;  ///< there was a map to register against (false for the first scan)
  /// The guess was the motion's prediction (a lidar alone, no odometry): a refused scan's pose is then
  /// nothing measured.
  bool predicted = false;
  /// How far off a prediction may have been, m (its GuessUncertainty): what the directions a partial
  /// correction took from it are worth.
  double guess_uncertainty = 0.0;
  Correction correction = Correction::kNone;
  RejectReason reason = RejectReason::kNone;  ///< fault control's, when the odometry guess was kept
  double rmse = 0.0;                          ///< m, over the final pairs
  /// For a partial correction (LocalizationUpdate's): map-frame directions along which the position, and
  /// axes about which the turn, came from odometry.
  std::vector<Eigen::Vector3d> odometry_directions;
  std::vector<Eigen::Vector3d> odometry_axes;
};

/// The thresholds. Scan counts suit both scanners: the stop-and-go scanner scans every 2 m, a lidar several
/// times a second; distances are what wheel odometry's error grows with (GraphLocalizerOptions's
/// odometry_sigma: 5 % of the distance).
struct LocalizationHealthOptions {
  /// Degraded after this many scans in a row kept odometry: one or two happen on any run (a sweep while
  /// turning, a person in front of the scanner); three in a row mean the scans stopped matching.
  std::size_t degraded_unmatched_scans = 3;
  /// Lost after this many scans in a row kept odometry (20 m for the stop-and-go scanner)...
  std::size_t lost_unmatched_scans = 10;
  /// ... or after odometry alone carried the pose this far, m: 5 % of it is 1 m, fault control's
  /// max_translation_jump, beyond which even the right match is refused as a jump: the localizer cannot
  /// find its way back by itself.
  double lost_unmatched_distance = 20.0;
  /// Without odometry (a lidar alone) a refused scan keeps the motion's prediction, which nothing
  /// measured: degraded at the first, lost after this many in a row. KAIST03 replayed at 16 times real
  /// time on a busy machine: 17 of 21 scans dropped, two refused in a row, 19 and 22 m off, said `ok`.
  std::size_t lost_predicted_scans = 2;
  /// And partial corrections that took a direction from predictions this uncertain, m, summed over those in
  /// a row (fault control's jump limit: a match that far off would be refused), are degraded: after a gap in
  /// the scans (KAIST03 at 16 times real time, 4-5 s between the scans processed) a road's scan matched along
  /// the road where the prediction put it, 14-22 m off; scan after scan, a 10 Hz lidar's 2.5 cm add up to it
  /// in 4 s of corridor.
  double degraded_prediction_uncertainty = 1.0;
  /// Degraded when, since the last full correction, odometry carried the pose along some direction
  /// (partial corrections, or none) this far, m: 5 % of it is 0.5 m, twice the fine ICP stage's 0.25 m
  /// correspondence bound, where the map starts to show doubled walls. On the simulated campus the error
  /// grew to 1-2 m (tilting scanner) and 4 m (lidar) over such stretches. Loop closures do not end a
  /// stretch: a loop edge counts only its well-constrained directions, so the one odometry carried mostly
  /// stays odometry's (on the campus, loops closed at every scan while the error stayed at 1-2 m for 80
  /// scans).
  double degraded_odometry_distance = 10.0;
  /// Degraded when this many correcting registrations in a row had an RMSE above `loose_fit_rmse`, m: on
  /// the simulated campus a scan's RMSE is 5-11 cm (tilting scanner) and 5-12 cm (lidar), above 10 cm for
  /// one scan in twenty and never three in a row; fault control rejects above 15 cm
  /// (FaultLimits::max_rmse).
  std::size_t loose_fit_scans = 3;
  double loose_fit_rmse = 0.10;
  /// ... or above `loose_fit_ratio` times the median RMSE of the run's last `loose_fit_window` correcting
  /// registrations, where that is higher: how closely scans fit depends on what they see. A real road's
  /// Ouster keyframes (KAIST03) fit at 9-12.5 cm, median 10, as closely as they ever do, 0.11 m from the
  /// reference at worst; at 10 cm a third of that run was degraded.
  double loose_fit_ratio = 1.5;
  std::size_t loose_fit_window = 50;
};

/// Classifies the localization from the scans' outcomes: a pure function of what it was fed, in order.
/// Not thread-safe: the localizer worker feeds it on its thread and publishes health().
class LocalizationHealthClassifier {
 public:
  explicit LocalizationHealthClassifier(LocalizationHealthOptions options = {}) : options_(options) {}

  /// After each scan the localizer processed.
  void classify(const ScanOutcome& scan);
  /// A search placed the robot at the scan of `stamp`: degraded until its next scans confirm it
  /// (confirm()) or contradict it (lose()).
  void placed(double stamp);
  /// Something besides the scan path confirmed the estimate (a loop closure, a place the next scans
  /// matched from): what odometry carried before it is forgiven, and a lost state ends.
  void confirm();
  /// The estimate was contradicted (`why`): lost until confirm().
  void lose(std::string why);

  [[nodiscard]] LocalizationHealth health() const;

 private:
  LocalizationHealthOptions options_;
  std::size_t scans_ = 0;
  bool have_position_ = false;
  Eigen::Vector2d last_position_ = Eigen::Vector2d::Zero();
  std::optional<double> placed_at_;  ///< a search's place waiting for the scans after it
  std::optional<std::string> lost_;  ///< why the estimate was contradicted, until confirmed
  /// Odometry alone: scans in a row that kept odometry, since when (stamp of the last matched scan) and
  /// how far.
  std::size_t unmatched_scans_ = 0;
  double last_matched_stamp_ = 0.0;
  double unmatched_distance_ = 0.0;
  /// Odometry along some direction: since the last full correction.
  double odometry_distance_ = 0.0;
  std::size_t loose_fits_ = 0;  ///< correcting registrations in a row with a loose fit
  std::deque<double> fits_;     ///< the RMSEs of the last loose_fit_window correcting registrations
  /// What counts as a loose fit now, m.
  [[nodiscard]] double loose_fit_limit() const;
  ScanOutcome last_;
  ScanOutcome last_partial_;  ///< the newest partial correction, for what odometry carried
  bool have_partial_ = false;
  /// The predictions' possible errors summed over the partial corrections in a row that took a direction
  /// from them.
  double weak_guess_uncertainty_ = 0.0;
};

}  // namespace strata

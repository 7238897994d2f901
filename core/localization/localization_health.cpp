#include "core/localization/localization_health.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace strata {
namespace {

/// Metres or seconds for people: one decimal below 10, whole numbers above.
std::string amount(double value, const char* unit) {
  char text[32];
  if (value < 9.95)
    std::snprintf(text, sizeof text, "%.1f %s", value, unit);
  else
    std::snprintf(text, sizeof text, "%.0f %s", value, unit);
  return text;
}

std::string scans_text(std::size_t scans) {
  return std::to_string(scans) + (scans == 1 ? " scan" : " scans");
}

/// Why a registration was not used, in plain words.
std::string_view why_kept(RejectReason reason, bool predicted) {
  switch (reason) {
    case RejectReason::kTooFewPairs:
      return "nothing to match";
    case RejectReason::kHighResidual:
      return "the surfaces did not fit";
    case RejectReason::kJumpFromGuess:
      return predicted ? "the match was too far from the prediction to trust"
                       : "the match was too far from odometry to trust";
    case RejectReason::kDegenerateGeometry:
      return "too few surfaces to fix the position";
    case RejectReason::kNone:
      break;
  }
  return "not used";
}

// A direction counts as along a map axis when it is within 67.5 degrees of it (a diagonal corridor is
// along x and y), and as vertical within 45 degrees of the vertical.
constexpr double kAlongAxis = 0.38;
constexpr double kVertical = 0.7;

/// What odometry supplied in a partial correction: "corridor: position along x", "open ground: position
/// along x,y and heading".
std::string from_odometry(const ScanOutcome& partial) {
  std::string axes;
  int horizontal = 0;
  for (int axis = 0; axis < 3; ++axis) {
    bool along = false;
    for (const Eigen::Vector3d& d : partial.odometry_directions)
      along = along || std::abs(d[axis]) >= kAlongAxis;
    if (along)
      axes += std::string(axes.empty() ? "" : ",") + "xyz"[axis];
  }
  for (const Eigen::Vector3d& d : partial.odometry_directions)
    horizontal += std::abs(d.z()) < kVertical ? 1 : 0;
  bool heading = false;
  bool tilt = false;
  for (const Eigen::Vector3d& a : partial.odometry_axes)
    (std::abs(a.z()) >= kVertical ? heading : tilt) = true;

  std::string what = axes.empty() ? "" : "position along " + axes;
  for (const auto& [taken, name] : {std::pair{heading, "heading"}, std::pair{tilt, "tilt"}})
    if (taken)
      what += std::string(what.empty() ? "" : " and ") + name;
  if (what.empty())
    what = "part of the pose";
  const char* where = horizontal >= 2 ? "open ground" : horizontal == 1 ? "corridor" : "few surfaces";
  return std::string(where) + ": " + what;
}

std::string placed_text(double stamp) {
  char text[96];
  std::snprintf(text, sizeof text, "placed by a search at t=%.1f: waiting for the next scans to match there",
                stamp);
  return text;
}

/// How far `step` went along `directions` (unit vectors, map frame; orthogonal): the part of the way
/// odometry carried.
double along(const Eigen::Vector2d& step, const std::vector<Eigen::Vector3d>& directions) {
  double squared = 0.0;
  for (const Eigen::Vector3d& d : directions)
    squared += std::pow(d.head<2>().dot(step), 2);
  return std::min(std::sqrt(squared), step.norm());
}

}  // namespace

std::string_view to_string(LocalizationState state) {
  switch (state) {
    case LocalizationState::kOk:
      return "ok";
    case LocalizationState::kDegraded:
      return "degraded";
    case LocalizationState::kLost:
      return "lost";
  }
  return "lost";
}

LocalizationHealth LocalizationHealth::no_scan_yet() {
  return {LocalizationState::kDegraded, "no scan yet: position from odometry only"};
}

void LocalizationHealthClassifier::classify(const ScanOutcome& scan) {
  const Eigen::Vector2d step =
      have_position_ ? Eigen::Vector2d(scan.position - last_position_) : Eigen::Vector2d::Zero();
  const double moved = step.norm();
  have_position_ = true;
  last_position_ = scan.position;
  ++scans_;
  last_ = scan;
  // Along a direction the scans leave open, nothing corrects a prediction: each scan's possible error adds
  // to the ones before (a lidar alone on the campus, in a corridor after a stop and a turn, kept the speed it
  // had in the turn, 0.1 m/s instead of 0.6, and was 18 m behind after 40 s, every scan `ok`).
  weak_guess_uncertainty_ =
      scan.predicted && scan.correction == Correction::kPartial && !scan.odometry_directions.empty()
          ? weak_guess_uncertainty_ + scan.guess_uncertainty
          : 0.0;
  if (scan.registered && scan.correction != Correction::kNone) {
    fits_.push_back(scan.rmse);
    if (fits_.size() > options_.loose_fit_window)
      fits_.pop_front();
    loose_fits_ = scan.rmse > loose_fit_limit() ? loose_fits_ + 1 : 0;
  }
  if (!scan.registered || scan.correction == Correction::kFull) {
    // Matched whole, or the first scan, which the map starts from: nothing rests on odometry.
    unmatched_scans_ = 0;
    unmatched_distance_ = 0.0;
    last_matched_stamp_ = scan.stamp;
    odometry_distance_ = 0.0;
    have_partial_ = false;
    return;
  }
  if (scan.correction == Correction::kPartial) {
    // Only the way odometry carried counts: along a corridor, its axis; a turn taken from the gyro
    // carries no position (on the campus the tilting scanner's partial scans said "degraded" for a whole
    // run, 394 m "from odometry" counted where the walls fixed all but the heading).
    odometry_distance_ += along(step, scan.odometry_directions);
    unmatched_scans_ = 0;
    unmatched_distance_ = 0.0;
    last_matched_stamp_ = scan.stamp;
    last_partial_ = scan;
    have_partial_ = true;
    return;
  }
  odometry_distance_ += moved;
  ++unmatched_scans_;
  unmatched_distance_ += moved;
}

double LocalizationHealthClassifier::loose_fit_limit() const {
  // The run's own fit, this scan's included, once a few scans tell it: a run whose every scan fits at
  // 11 cm (a road's first keyframes) fits as closely as it can.
  constexpr std::size_t kEnoughFits = 3;
  if (fits_.size() < kEnoughFits)
    return options_.loose_fit_rmse;
  std::vector<double> sorted(fits_.begin(), fits_.end());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  return std::max(options_.loose_fit_rmse, options_.loose_fit_ratio * sorted[sorted.size() / 2]);
}

void LocalizationHealthClassifier::placed(double stamp) {
  placed_at_ = stamp;
  lost_.reset();
}

void LocalizationHealthClassifier::confirm() {
  placed_at_.reset();
  lost_.reset();
  odometry_distance_ = 0.0;
  weak_guess_uncertainty_ = 0.0;
  unmatched_scans_ = 0;
  unmatched_distance_ = 0.0;
}

void LocalizationHealthClassifier::lose(std::string why) {
  placed_at_.reset();
  lost_ = std::move(why);
}

LocalizationHealth LocalizationHealthClassifier::health() const {
  using enum LocalizationState;
  if (scans_ == 0)
    return LocalizationHealth::no_scan_yet();
  // Without odometry, what a refused scan keeps is the prediction from the scans before.
  const bool predicted = last_.predicted;
  const std::string source = predicted ? "the prediction" : "odometry";
  const std::string why = std::string(why_kept(last_.reason, predicted));
  const std::string kept = unmatched_scans_ == 1
                               ? "the last scan kept " + source + ": " + why
                               : scans_text(unmatched_scans_) + " in a row kept " + source + ": " + why;
  const std::size_t lost_after = predicted ? options_.lost_predicted_scans : options_.lost_unmatched_scans;
  const std::size_t degraded_after = predicted ? 1 : options_.degraded_unmatched_scans;
  if (unmatched_scans_ >= lost_after ||
      (unmatched_scans_ > 0 && unmatched_distance_ >= options_.lost_unmatched_distance)) {
    return {kLost, "no scan matched for " + scans_text(unmatched_scans_) + " (" +
                       amount(last_.stamp - last_matched_stamp_, "s") + ", " +
                       amount(unmatched_distance_, "m") + "): position from " + source + " only"};
  }
  if (lost_)
    return {kLost, *lost_};
  if (placed_at_)
    return {kDegraded, placed_text(*placed_at_)};
  if (unmatched_scans_ >= degraded_after)
    return {kDegraded, kept};
  // A turn taken from the gyro carries no distance: said without one.
  const std::string carried = (have_partial_ ? from_odometry(last_partial_) : std::string("position")) +
                              " from " + source +
                              (odometry_distance_ < 0.05 ? "" : " for " + amount(odometry_distance_, "m"));
  if (weak_guess_uncertainty_ >= options_.degraded_prediction_uncertainty)
    return {kDegraded, carried + ", which may be " + amount(weak_guess_uncertainty_, "m") + " off"};
  if (odometry_distance_ >= options_.degraded_odometry_distance)
    return {kDegraded, unmatched_scans_ > 0 ? carried + "; " + kept : carried};
  if (unmatched_scans_ > 0)
    return {kOk, kept};
  if (!last_.registered)
    return {kOk, "first scan: the map starts here"};
  if (loose_fits_ >= options_.loose_fit_scans)
    return {kDegraded, scans_text(loose_fits_) + " in a row fit the map only loosely: the last " +
                           amount(last_.rmse * 100.0, "cm") + " apart"};
  if (last_.correction == Correction::kPartial)
    return {kOk, carried};
  return {kOk, "the last scan matched the map"};
}

}  // namespace strata

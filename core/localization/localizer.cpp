#include "core/localization/localizer.hpp"

#include <utility>

namespace strata {
namespace {

/// What the health classifier is told of one scan.
ScanOutcome outcome_of(const LocalizationUpdate& update, const ScanToLocalize& scan) {
  ScanOutcome outcome;
  outcome.stamp = scan.stamp;
  outcome.predicted = !scan.odometry;
  outcome.position = update.pose.translation().head<2>();
  outcome.registered = update.registration.has_value();
  outcome.correction = update.correction;
  if (update.registration) {
    outcome.reason = update.registration->assessment.reason;
    outcome.rmse = update.registration->rmse;
  }
  outcome.odometry_directions = update.odometry_directions;
  outcome.odometry_axes = update.odometry_axes;
  if (update.guess_uncertainty)
    outcome.guess_uncertainty = update.guess_uncertainty->translation;
  return outcome;
}

}  // namespace

Localizer::Localizer(GraphLocalizerOptions options, const Eigen::Isometry3d& initial_map_from_odom,
                     LocalizationHealthOptions health)
    : graph_(std::move(options), initial_map_from_odom), health_(health) {}

LocalizedScan Localizer::localize(ScanToLocalize& scan) {
  // 1b The revolution's points as if measured at once, at the stamp: the map and the searches get them so.
  graph_.deskew(scan.points, scan.times, scan.odometry, scan.stamp);
  scan.times = {};
  // In a saved map, an operator's estimate or the places followed: found, the scan registers from there.
  if (const std::optional<Eigen::Isometry3d> found = search_before_registering(scan))
    place(*found, scan);
  // 2-5 Guess, register, fault check, pose; a keyframe for the pose graph.
  LocalizedScan result;
  result.update = graph_.add_scan(scan.points, scan.odometry, scan.stamp, scan.sensor_origin, scan.gravity,
                                  scan.standing_gyro);
  result.map_from_odom = result.update.map_from_odom;
  result.anchor = graph_.anchor();
  judge(scan, result.update);
  // Lost in a saved map: the robot is searched for everywhere the map's robot drove; found, the next scan
  // starts there (and confirms it or not).
  if (tracker_ && health_.health().state == LocalizationState::kLost) {
    if (const std::optional<Eigen::Isometry3d> found =
            tracker_->search_while_lost(scan.points, scan.odometry, scan.stamp))
      result.map_from_odom = place(*found, scan);
  } else if (tracker_) {
    tracker_->not_lost();
  }
  // A search may have moved the correction after the registration.
  result.pose = result.map_from_odom * result.update.map_from_odom.inverse() * result.update.pose;
  result.health = health_.health();
  if (!scan.odometry)
    result.velocity = graph_.velocity(std::nullopt, scan.stamp);
  if (tracker_)
    result.searches = tracker_->take_reports();
  latest_ = scan;
  return result;
}

std::optional<Eigen::Isometry3d> Localizer::search_before_registering(const ScanToLocalize& scan) {
  if (!tracker_)
    return std::nullopt;
  if (const std::optional<PoseEstimate> hint = std::exchange(hint_, std::nullopt))
    return tracker_->search_around(*hint, scan.points, scan.odometry, scan.stamp);
  return tracker_->follow(scan.points, scan.odometry, scan.stamp);
}

Eigen::Isometry3d Localizer::place(const Eigen::Isometry3d& pose, const ScanToLocalize& scan) {
  health_.placed(scan.stamp);
  tracker_->placed(scan.stamp);
  return graph_.place(pose, scan.odometry, scan.stamp);
}

void Localizer::judge(const ScanToLocalize& scan, const LocalizationUpdate& update) {
  health_.classify(outcome_of(update, scan));
  // A loop closure measured the estimate against the map made long before: what odometry carried since
  // is accounted for.
  const std::size_t loops = graph_.status().loops;
  if (loops > std::exchange(loops_seen_, loops))
    health_.confirm();
  if (!tracker_)
    return;
  switch (tracker_->check_placement(update, scan.stamp)) {
    case PlacementCheck::kConfirmed:
      health_.confirm();  // the scans after a search's place matched there
      break;
    case PlacementCheck::kContradicted:
      health_.lose("the place a search found was wrong: the next scans were refused there");
      break;
    case PlacementCheck::kNone:
    case PlacementCheck::kPending:
      break;
  }
}

void Localizer::localize_in(std::shared_ptr<const LocalizationMap> map) {
  tracker_ = map ? std::make_unique<RelocalizationTracker>(map) : nullptr;
  hint_.reset();
  graph_.localize_in(std::move(map));
  loops_seen_ = 0;
}

std::optional<LatestScanSearch> Localizer::search_with_latest_scan(const PoseEstimate& hint,
                                                                   const std::optional<Pose2>& odometry_now) {
  if (!tracker_ || !latest_)
    return std::nullopt;
  // The hint is where the robot is now; the scan was taken where it was then. The odometry since carries
  // it back (nothing, for a robot standing still).
  PoseEstimate at_scan = hint;
  if (odometry_now && latest_->odometry) {
    const Pose2 back = Pose2{hint.x, hint.y, hint.yaw}.compose(latest_->odometry->relative_to(*odometry_now));
    at_scan.x = back.x;
    at_scan.y = back.y;
    at_scan.yaw = back.theta;
  }
  LatestScanSearch result{.stamp = latest_->stamp};
  if (const std::optional<Eigen::Isometry3d> found =
          tracker_->search_around(at_scan, latest_->points, latest_->odometry, latest_->stamp))
    result.map_from_odom = place(*found, *latest_);
  result.health = health_.health();
  result.searches = tracker_->take_reports();
  return result;
}

}  // namespace strata

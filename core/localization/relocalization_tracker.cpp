#include "core/localization/relocalization_tracker.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace strata {
namespace {

/// Following the places a search found fitting as well: a scan is looked at once the robot has moved this
/// far or turned this much since the last one looked at (the same view again decides nothing). How far
/// they are followed, and how often a lost robot is searched for: RelocalizationOptions.
constexpr double kFollowStep = 0.5;
constexpr double kFollowTurn = 0.35;

std::string looked_for(std::size_t places) {
  if (places == 1)
    return "; the robot is looked for at this place as it drives on";
  return "; the robot is looked for at these " + std::to_string(places) + " places as it drives on";
}

}  // namespace

RelocalizationTracker::RelocalizationTracker(std::shared_ptr<const LocalizationMap> map,
                                             RelocalizationOptions options)
    : relocalizer_(std::move(map), options) {}

void RelocalizationTracker::report(RelocalizationReport::Search search, double stamp,
                                   const RelocalizationResult& found, std::string message) {
  reports_.push_back({.search = search,
                      .stamp = stamp,
                      .found = found.found,
                      .message = std::move(message),
                      .candidates = found.candidates,
                      .seconds = found.seconds});
}

std::optional<Eigen::Isometry3d> RelocalizationTracker::search_around(const PoseEstimate& hint,
                                                                      const PointCloud& points,
                                                                      const std::optional<Pose2>& odometry,
                                                                      double stamp) {
  const RelocalizationResult found = relocalizer_.around(points, hint.x, hint.y, hint.yaw, hint.z);
  std::string message = found.message;
  following_.reset();
  unconfirmed_.reset();  // the operator's word replaces an earlier search's
  // Not found, its places (or its best candidate, where none fitted well enough) are judged by the
  // robot's next scans as it drives on.
  if (const std::vector<Eigen::Isometry3d> places = found.places_to_follow(); !places.empty() && odometry) {
    following_ = Following{places, *odometry};
    message += looked_for(places.size());
  }
  report(RelocalizationReport::Search::kHint, stamp, found, std::move(message));
  return found.found ? std::optional(found.pose) : std::nullopt;
}

std::optional<Eigen::Isometry3d> RelocalizationTracker::follow(const PointCloud& points,
                                                               const std::optional<Pose2>& odometry,
                                                               double stamp) {
  if (!following_ || !odometry)
    return std::nullopt;
  Following& following = *following_;
  const Pose2 moved = odometry->relative_to(following.odometry);
  if (std::hypot(moved.x, moved.y) < kFollowStep && std::abs(moved.theta) < kFollowTurn)
    return std::nullopt;  // the same view again
  const Eigen::Isometry3d motion = Pose3::from_pose2(moved).to_isometry();
  std::vector<Eigen::Isometry3d> places = following.places;
  for (Eigen::Isometry3d& place : places)
    place = place * motion;
  const RelocalizationResult found = relocalizer_.follow(points, places);
  ++following.scans;
  following.metres += std::hypot(moved.x, moved.y);
  std::string message = found.message;
  if (found.found) {
    following_.reset();
  } else if (!found.places.empty() && following.metres < options().follow_metres) {
    following.places = found.places;
    following.odometry = *odometry;
    message += looked_for(found.places.size());
  } else {
    message += " (after " + std::to_string(following.scans) + " scans over " +
               std::to_string(static_cast<int>(std::lround(following.metres))) + " m as the robot drove on)";
    following_.reset();
  }
  report(RelocalizationReport::Search::kFollow, stamp, found, std::move(message));
  return found.found ? std::optional(found.pose) : std::nullopt;
}

std::optional<Eigen::Isometry3d> RelocalizationTracker::search_while_lost(
    const PointCloud& points, const std::optional<Pose2>& odometry, double stamp) {
  // Not while places are being followed: they are where to look, and the whole map would fit as many
  // places again. A search takes 0.1-2.5 s on the scan path (docs/benchmarks.md, "Finding the robot").
  if (following_ || lost_scans_++ % options().lost_search_every != 0)
    return std::nullopt;
  const RelocalizationResult found = relocalizer_.anywhere(points);
  std::string message = "lost: " + found.message;
  if (!found.found && found.places.size() > 1 && odometry) {
    following_ = Following{found.places, *odometry};
    message += looked_for(found.places.size());
  }
  report(RelocalizationReport::Search::kWholeMap, stamp, found, std::move(message));
  return found.found ? std::optional(found.pose) : std::nullopt;
}

void RelocalizationTracker::placed(double stamp) {
  unconfirmed_ = Unconfirmed{.stamp = stamp};
  lost_scans_ = 0;
}

PlacementCheck RelocalizationTracker::check_placement(const LocalizationUpdate& update, double stamp) {
  if (!unconfirmed_)
    return PlacementCheck::kNone;
  if (stamp <= unconfirmed_->stamp || !update.registration)
    return PlacementCheck::kPending;  // the scan it was found with agrees with itself
  Unconfirmed& place = *unconfirmed_;
  const bool matched = update.correction != Correction::kNone;
  ++(matched ? place.matched : place.refused);
  char text[160];
  RelocalizationResult result;
  if (place.matched >= options().confirm_scans) {
    std::snprintf(text, sizeof text,
                  "the place found at t=%.1f is confirmed: the next %zu scans matched there", place.stamp,
                  place.matched);
    result.found = true;
    unconfirmed_.reset();
    report(RelocalizationReport::Search::kCheck, stamp, result, text);
    return PlacementCheck::kConfirmed;
  }
  if (place.refused >= options().contradict_scans) {
    std::snprintf(text, sizeof text,
                  "the place found at t=%.1f was wrong: %zu of the next scans were refused there",
                  place.stamp, place.refused);
    unconfirmed_.reset();
    report(RelocalizationReport::Search::kCheck, stamp, result,
           std::string(text) + " (" + update.registration->assessment.message + ")");
    return PlacementCheck::kContradicted;
  }
  return PlacementCheck::kPending;
}

}  // namespace strata

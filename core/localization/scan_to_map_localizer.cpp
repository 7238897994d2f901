#include "core/localization/scan_to_map_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace strata {
namespace {

/// How close a retry from the second guess must land to the first registration to confirm it: two ICP
/// runs into one minimum agree to millimetres.
constexpr double kRetryAgreement = 0.05;                           // metres
constexpr double kRetryAgreementAngle = std::numbers::pi / 180.0;  // radians: 1 degree

/// How much of ICP's turn about the vertical a partial scan keeps, the rest being the odometry's: as much as
/// its surfaces resist turning (LocalizerOptions::sliding_yaw_full_information), and as much as the gyro may
/// have drifted over the way since the last scan: a complementary filter, the gyro for the short term and
/// the walls for the long. None for a turn no gyro drifts between two scans (a false minimum).
double sliding_yaw_weight(const LocalizerOptions& options, const TranslationConstraint& constraint,
                          double icp_yaw_change, std::optional<double> moved) {
  if (std::abs(icp_yaw_change) > options.sliding_yaw_max_change)
    return 0.0;
  const double information = rotation_information(constraint, Eigen::Vector3d::UnitZ());
  const double span = options.sliding_yaw_full_information - options.weak_rotation_guard;
  const double surfaces =
      span > 0.0 ? std::clamp((information - options.weak_rotation_guard) / span, 0.0, 1.0) : 1.0;
  const double way = moved && options.sliding_yaw_distance > 0.0
                         ? 1.0 - std::exp(-*moved / options.sliding_yaw_distance)
                         : 1.0;
  return options.sliding_yaw_weight * surfaces * way;
}

/// The share of the scan's points a registration paired: a wrong match after a turn the prediction
/// missed pairs few (LocalizerOptions::turn_search).
double pairing(const RegistrationResult& result) {
  return result.source_points == 0
             ? 0.0
             : static_cast<double>(result.pairs) / static_cast<double>(result.source_points);
}

Eigen::Matrix3d about_vertical(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

std::string_view to_string(Correction correction) {
  switch (correction) {
    case Correction::kNone:
      return "none";
    case Correction::kPartial:
      return "partial";
    case Correction::kFull:
      return "full";
  }
  return "none";
}

ScanToMapLocalizer::ScanToMapLocalizer(LocalizerOptions options,
                                       const Eigen::Isometry3d& initial_map_from_odom)
    : options_(std::move(options)),
      registration_(options_.registration),
      local_map_(options_.local_map_voxel, options_.local_map_scans, options_.local_map_metres),
      // A start at a given pose knows its tilt; one at the odometry's origin does not.
      leveling_(options_.gravity, !initial_map_from_odom.isApprox(Eigen::Isometry3d::Identity())) {
  global_.apply_correction(initial_map_from_odom);
}

void ScanToMapLocalizer::correct(const Eigen::Isometry3d& correction) {
  global_.apply_correction(correction);
  local_map_.transform(correction);
}

void ScanToMapLocalizer::localize_in(std::shared_ptr<const LocalizationMap> map) {
  local_map_ = LocalMap(options_.local_map_voxel, options_.local_map_scans, options_.local_map_metres);
  saved_registration_.reset();
  saved_map_ = std::move(map);
  if (saved_map_ == nullptr)
    return;
  // The whole map in one index: a lookup costs the same in a big tree as in a cropped one, and its
  // normals, estimated where scans reach, are kept for the next scans there.
  saved_registration_ = std::make_unique<ScanRegistration>(options_.registration);
  saved_registration_->set_thinned_target(saved_map_->cloud());
}

LocalizationUpdate ScanToMapLocalizer::add_scan(const PointCloud& points, const Pose2& odometry,
                                                const std::optional<GravityReading>& gravity,
                                                GuessSource source,
                                                const std::optional<GuessUncertainty>& uncertainty,
                                                const std::optional<Eigen::Isometry3d>& second_guess,
                                                double heading_drift) {
  // Guess: the last correction carried forward by the odometry since (docs/architecture.md 3, step 2).
  // Its tilt is the last scan's; gravity, where there is a reading, knows the tilt now (a ramp begun).
  // A reading GravityLeveling cannot use (not a unit vector, no sigma) is as good as none.
  const std::optional<GravityReading> up =
      gravity && GravityLeveling::usable(*gravity) ? gravity : std::nullopt;
  const Eigen::Isometry3d odometry_guess = global_.pose_isometry(odometry);
  Eigen::Isometry3d guess = odometry_guess;
  guess.linear() = about_vertical(heading_drift) * guess.linear();
  // Metres driven since the last scan, by the odometry: how far its tilt and heading may be stale.
  const std::optional<double> moved =
      last_odometry_
          ? std::optional(std::hypot(odometry.x - last_odometry_->x, odometry.y - last_odometry_->y))
          : std::nullopt;
  // The guess's tilt is for the registration. A scan with nothing to register against (the first) is
  // levelled below by the same reading: taken here too, it counted twice, and a given start took 0.59 of
  // the reading's error as its tilt instead of 0.38 (docs/benchmarks.md, "The first scan's tilt").
  const bool registering = saved_registration_ != nullptr || !local_map_.empty();
  if (up && registering)
    guess.linear() = leveling_.align(guess, *up, moved) * guess.linear();
  last_odometry_ = odometry;
  LocalizationUpdate update;
  update.pose = guess;
  if (source == GuessSource::kPrediction)
    update.guess_uncertainty = uncertainty;
  if (registering) {
    RegistrationResult result = register_from(points, guess, source, uncertainty, second_guess, update);
    // Weak directions come from the guess, unless the guess knows nothing (a lidar alone's first scans).
    const bool guess_informs = !uncertainty || uncertainty->motion_known;
    use_registration(std::move(result), guess, source, guess_informs, moved, update);
  }
  // Scan matching's tilt, levelled toward gravity by how far each is to be trusted: what stops the
  // height walking (a tilt error becomes height error with every metre). Not after a rejected scan: its
  // odometry is in doubt, and a scan fault control refused changes nothing.
  const bool used = update.correction != Correction::kNone || !update.registration;
  if (up && used) {
    update.pose.linear() = leveling_.level(update.pose, *up) * update.pose.linear();
    update.gravity = leveling_.corrected(*up);
  }
  if (used && (update.correction != Correction::kNone || up))
    global_.apply_correction(update.pose * odometry_guess.inverse());
  update.map_from_odom = global_.correction();

  if (saved_map_ == nullptr)
    local_map_.add(points, update.pose, sensor_origin_);
  return update;
}

RegistrationResult ScanToMapLocalizer::register_from(const PointCloud& points, Eigen::Isometry3d& guess,
                                                     GuessSource source,
                                                     const std::optional<GuessUncertainty>& uncertainty,
                                                     const std::optional<Eigen::Isometry3d>& second_guess,
                                                     LocalizationUpdate& update) {
  FaultLimits limits = options_.registration.limits;
  if (uncertainty) {
    limits.max_translation_jump += uncertainty->translation;
    limits.max_rotation_jump += uncertainty->rotation;
  }
  const bool mapping = saved_registration_ == nullptr;
  ScanRegistration& registration = mapping ? registration_ : *saved_registration_;
  if (mapping) {
    registration_.follow_target(local_map_.points(), local_map_.layout(), local_map_.take_normals(),
                                local_map_.viewpoints());
    registration_.set_source_viewpoint(sensor_origin_);
  }
  RegistrationResult result = registration.register_scan(points, guess, limits);
  const double missable_turn = uncertainty ? uncertainty->rotation : 0.0;
  if (source == GuessSource::kPrediction && missable_turn >= options_.turn_search.from &&
      pairing(result) < options_.turn_search.poor_pairing) {
    if (std::optional<double> turn =
            search_turns(registration, points, guess, limits, missable_turn, result)) {
      guess.linear() = about_vertical(*turn) * guess.linear();  // what weak directions come from, if any
      update.turn_found = turn;
    }
  }
  if (result.assessment.reason == RejectReason::kJumpFromGuess && second_guess) {
    // Far from the odometry: either ICP slid, or the odometry is off (wheels slipping, a bump). From a
    // second, independent guess a slide lands elsewhere; a true pose is found again, near that guess.
    RegistrationResult retry = registration.register_scan(points, *second_guess, limits);
    const Eigen::Isometry3d between = result.refined.inverse() * retry.refined;
    if (retry.accepted() && between.translation().norm() < kRetryAgreement &&
        Eigen::AngleAxisd(between.linear()).angle() < kRetryAgreementAngle) {
      retry.seconds += result.seconds;
      result = std::move(retry);
      guess = *second_guess;  // what the weakly constrained directions come from, if any
      update.retried = true;
    }
  }
  if (mapping)
    local_map_.keep_normals(registration_.take_normals());
  return result;
}

std::optional<double> ScanToMapLocalizer::search_turns(ScanRegistration& registration,
                                                       const PointCloud& points,
                                                       const Eigen::Isometry3d& guess,
                                                       const FaultLimits& limits, double missable_turn,
                                                       RegistrationResult& result) const {
  const TurnSearchOptions& search = options_.turn_search;
  const double step =
      search.turns.size() >= 2 ? search.turns.back() - search.turns[search.turns.size() - 2] : 0.0;
  double seconds = result.seconds;
  std::optional<RegistrationResult> best;
  double best_turn = 0.0;
  for (const double turn : search.turns) {
    if (std::abs(turn) > missable_turn + step)
      continue;  // further than the base can have turned unforeseen (and one step of the search)
    Eigen::Isometry3d turned = guess;
    turned.linear() = about_vertical(turn) * guess.linear();
    RegistrationResult candidate = registration.register_scan(points, turned, limits);
    seconds += candidate.seconds;
    if (candidate.accepted() && (!best || pairing(candidate) > pairing(*best))) {
      best = std::move(candidate);
      best_turn = turn;
    }
  }
  const bool clearly_better = best && pairing(*best) > pairing(result) + search.clearly_more;
  if (clearly_better)
    result = std::move(*best);
  result.seconds = seconds;
  return clearly_better ? std::optional(best_turn) : std::nullopt;
}

void ScanToMapLocalizer::use_registration(RegistrationResult result, const Eigen::Isometry3d& guess,
                                          GuessSource source, bool guess_informs, std::optional<double> moved,
                                          LocalizationUpdate& update) const {
  const bool weak =
      guess_informs && (result.constraint.weakest < options_.weak_direction_guard ||
                        result.constraint.rotation_eigenvalues[0] < options_.weak_rotation_guard);
  const bool only_degenerate = result.assessment.reason == RejectReason::kDegenerateGeometry;
  if (weak && (result.accepted() || only_degenerate)) {
    // Keep ICP's answer except along the directions no surface faces (a corridor's axis; both ways
    // along an open plane): there, odometry knows better.
    update.pose = result.refined;
    // Rotation: remove the turn about weakly constrained axes from ICP's change to the guess.
    Eigen::AngleAxisd change(result.refined.linear() * guess.linear().transpose());
    Eigen::Vector3d turn = change.axis() * change.angle();
    for (int k = 0; k < 3; ++k) {
      if (result.constraint.rotation_eigenvalues[k] >= options_.weak_rotation_guard)
        continue;
      const Eigen::Vector3d axis = result.constraint.rotation_axes.col(k);
      turn -= axis * axis.dot(turn);
      update.odometry_axes.push_back(axis);
    }
    // A scan that slides has few surfaces: its yaw is weighed against measured odometry's.
    const bool sliding = result.constraint.weakest < options_.weak_direction_guard;
    if (sliding && source == GuessSource::kOdometry) {
      const Eigen::Vector3d vertical = Eigen::Vector3d::UnitZ();
      const bool taken = std::ranges::any_of(
          update.odometry_axes, [&](const Eigen::Vector3d& a) { return std::abs(a.dot(vertical)) > 0.9; });
      const double weight = sliding_yaw_weight(options_, result.constraint, vertical.dot(turn), moved);
      turn -= vertical * vertical.dot(turn) * (1.0 - weight);
      if (!taken && weight < 0.5)  // mostly the odometry's: what the status's explanation says
        update.odometry_axes.push_back(vertical);
    }
    update.pose.linear() = rotation_from_vector(turn) * guess.linear();
    const Eigen::Vector3d offset = guess.translation() - result.refined.translation();
    for (int k = 0; k < 3; ++k) {
      if (result.constraint.eigenvalues[k] >= options_.weak_direction_guard)
        continue;
      const Eigen::Vector3d d = result.constraint.directions.col(k);
      update.pose.translation() += d * d.dot(offset);
      update.odometry_directions.push_back(d);
    }
    update.correction = Correction::kPartial;
  } else if (result.accepted()) {
    update.pose = result.transform;
    update.correction = Correction::kFull;
  }
  update.registration = std::move(result);
}

}  // namespace strata

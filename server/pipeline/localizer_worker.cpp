#include "server/pipeline/localizer_worker.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <numbers>
#include <string>
#include <utility>

#include "server/pipeline/scan_preprocessing.hpp"

namespace strata::pipeline {
namespace {

/// This thread's CPU time, ms: what a scan costs one core, whatever else the machine runs.
double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

/// Following the places a search found fitting as well: a scan is looked at once the robot has moved this
/// far or turned this much since the last one looked at (the same view again decides nothing). How far
/// they are followed, and how often a lost robot is searched for: RelocalizationOptions.
constexpr double kFollowStep = 0.5;
constexpr double kFollowTurn = 0.35;

std::string looked_for(std::size_t places) {
  if (places == 1)
    return "; the robot is looked for at this place as it drives on";
  return fmt::format("; the robot is looked for at these {} places as it drives on", places);
}

}  // namespace

LocalizerWorker::LocalizerWorker(RobotState& state, GraphLocalizerOptions options,
                                 const Eigen::Isometry3d& initial_map_from_odom)
    : state_(state), localizer_(std::move(options), initial_map_from_odom) {
  state_.set_correction(initial_map_from_odom, false);
}

LocalizerWorker::~LocalizerWorker() {
  stop();
}

void LocalizerWorker::start() {
  if (thread_.joinable())
    return;
  thread_ = std::thread([this] { run(); });
  loop_thread_ = std::thread([this] { close_loops(); });
}

void LocalizerWorker::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  idle_.notify_all();
  graph_wake_.notify_all();
  if (thread_.joinable())
    thread_.join();
  if (loop_thread_.joinable())
    loop_thread_.join();  // an optimization under way finishes first (a second or less)
}

void LocalizerWorker::keep_imu_calibration(ImuCalibrationStore& store) {
  calibration_ = &store;
  if (const std::optional<ImuCalibration> kept = store.load())
    localizer_.start_from_calibration(Eigen::Vector3d(kept->mounting.x(), kept->mounting.y(), 0.0));
  status_.imu_calibration = store.imu_calibration();
  status_.graph = localizer_.status();  // the mounting error it starts from, before the first scan
  state_.set_registration(status_);
}

void LocalizerWorker::close_loops() {
  while (true) {
    {
      std::unique_lock lock(mutex_);
      graph_wake_.wait(lock, [this] { return stopping_ || scans_for_the_graph_ > 0; });
      if (stopping_)
        return;
      scans_for_the_graph_ = 0;
    }
    try {
      if (localizer_.close_loops()) {
        const PoseGraphStatus graph = localizer_.status();
        spdlog::info(
            "localization: loop closed at t={:.1f}, {:.2f} m of drift corrected ({} loops over {} "
            "keyframes, optimized in {:.2f} s; the odometry's heading drifts {:.1f} degrees an hour; the "
            "IMU is mounted {:.2f} degrees rolled, {:.2f} pitched)",
            graph.last_loop_stamp, graph.last_correction, graph.loops, graph.keyframes,
            graph.last_optimization_seconds, graph.heading_drift_deg_per_h(),
            graph.gravity_mounting_deg().x(), graph.gravity_mounting_deg().y());
        if (calibration_ != nullptr)
          calibration_->update(graph);
        if (keyframes_sink_)
          keyframes_sink_(localizer_.keyframes());
      }
    } catch (const std::exception& error) {  // the scan path goes on without the graph's corrections
      spdlog::error("localization: the pose graph failed: {}", error.what());
    }
  }
}

void LocalizerWorker::submit(ScanEvent scan) {
  if (scan.received_at == 0.0)
    scan.received_at =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  {
    std::lock_guard lock(mutex_);
    if (pending_)
      ++dropped_;
    pending_ = std::move(scan);
  }
  wake_.notify_one();
}

bool LocalizerWorker::flush() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return stopping_ || (!pending_ && !busy_); });
  return !stopping_;
}

void LocalizerWorker::run() {
  while (true) {
    std::optional<ScanEvent> scan;
    std::optional<std::shared_ptr<const LocalizationMap>> map;
    std::optional<PoseEstimate> estimate;
    {
      std::unique_lock lock(mutex_);
      // A map or a pose estimate is taken up at once: a stop-and-go scanner standing still takes no next
      // scan. The estimate is searched with the latest scan, or the next when there is none yet.
      wake_.wait(lock, [this] {
        return stopping_ || pending_ || pending_map_ || (pending_estimate_ && latest_scan_kept_);
      });
      if (stopping_)
        return;
      map = std::exchange(pending_map_, std::nullopt);
      if (pending_) {
        scan = std::exchange(pending_, std::nullopt);
        status_.dropped = dropped_;
      } else if (latest_scan_kept_) {
        estimate = std::exchange(pending_estimate_, std::nullopt);
      }
      busy_ = true;
    }
    if (map)
      take_up(std::move(*map));
    if (scan)
      process(std::move(*scan));
    else if (estimate)
      search_with_latest_scan(*estimate);
    {
      std::lock_guard lock(mutex_);
      busy_ = false;
    }
    idle_.notify_all();
  }
}

void LocalizerWorker::take_up(std::shared_ptr<const LocalizationMap> map) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t points = map ? map->points.size() : 0;
  relocalizer_ = map ? std::make_unique<Relocalizer>(map) : nullptr;
  following_.reset();
  localizer_.localize_in(std::move(map));
  if (localizer_.localizing()) {
    spdlog::info("localizing in the loaded map ({} points, indexed in {:.2f} s): it is not changed", points,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } else {
    spdlog::info("mapping: scans are registered against the recent scans and go into the map");
  }
}

void LocalizerWorker::classify(const ScanEvent& scan, const LocalizationUpdate& update) {
  ScanOutcome outcome;
  outcome.stamp = scan.stamp;
  outcome.odometry = scan.odometry.position.head<2>();
  outcome.registered = update.registration.has_value();
  outcome.correction = update.correction;
  if (update.registration) {
    outcome.reason = update.registration->assessment.reason;
    outcome.rmse = update.registration->rmse;
  }
  outcome.odometry_directions = update.odometry_directions;
  outcome.odometry_axes = update.odometry_axes;
  health_.add_scan(outcome);
  const LocalizationHealth health = health_.health();
  if (health.state != status_.localization.state) {  // the log says when it changes, both ways
    const auto log_level = health.state == LocalizationState::kOk ? spdlog::level::info : spdlog::level::warn;
    spdlog::log(log_level, "localization {} at t={:.1f}: {}", to_string(health.state), scan.stamp,
                health.reason);
  }
  status_.localization = health;
}

void LocalizerWorker::localize_in(std::shared_ptr<const LocalizationMap> map) {
  std::lock_guard lock(mutex_);
  localizing_ = map != nullptr;
  pending_estimate_.reset();
  pending_map_ = std::move(map);
  wake_.notify_one();
}

CommandResult LocalizerWorker::set_pose_estimate(const PoseEstimate& estimate) {
  if (!std::isfinite(estimate.x) || !std::isfinite(estimate.y) || !std::isfinite(estimate.yaw) ||
      (estimate.z && !std::isfinite(*estimate.z)))
    return CommandResult::failure(ErrorCode::kBadParams, "the pose estimate must be finite numbers");
  std::lock_guard lock(mutex_);
  if (!localizing_) {
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "the robot localizes in no saved map: a pose estimate needs a map loaded "
        "to localize in (mode localize); while mapping, the map is where the scans put "
        "the robot");
  }
  pending_estimate_ = estimate;
  wake_.notify_one();
  CommandResult result = CommandResult::success();
  result.message =
      "the robot is searched for within 2 m and 30 degrees of it; the status's relocalization says "
      "how it went";
  return result;
}

std::optional<Eigen::Isometry3d> LocalizerWorker::search_around(const PoseEstimate& estimate,
                                                                const PointCloud& points,
                                                                const std::optional<Pose2>& odometry,
                                                                double stamp) {
  const RelocalizationResult found =
      relocalizer_->around(points, estimate.x, estimate.y, estimate.yaw, estimate.z);
  std::string message = found.message;
  following_.reset();
  // Not found, its places (or its best candidate, where none fitted well enough) are judged by the
  // robot's next scans as it drives on.
  if (const std::vector<Eigen::Isometry3d> places = found.places_to_follow(); !places.empty() && odometry) {
    following_ = Following{places, *odometry};
    message += looked_for(places.size());
  }
  status_.relocalization = RegistrationStatus::Relocalization{stamp, found.found, message};
  spdlog::info("pose estimate ({:.2f}, {:.2f}, {:.0f} degrees): {} ({} candidates, {:.2f} s)", estimate.x,
               estimate.y, estimate.yaw * 180.0 / std::numbers::pi, message, found.candidates, found.seconds);
  if (!found.found)
    return std::nullopt;
  return localizer_.place(found.pose, odometry, stamp);
}

void LocalizerWorker::follow_places(const PointCloud& points, const Pose2& odometry, double stamp) {
  Following& following = *following_;
  const Pose2 moved = odometry.relative_to(following.odometry);
  if (std::hypot(moved.x, moved.y) < kFollowStep && std::abs(moved.theta) < kFollowTurn)
    return;  // the same view again
  const Eigen::Isometry3d motion = Pose3::from_pose2(moved).to_isometry();
  std::vector<Eigen::Isometry3d> places = following.places;
  for (Eigen::Isometry3d& place : places)
    place = place * motion;
  const RelocalizationResult found = relocalizer_->follow(points, places);
  ++following.scans;
  following.metres += std::hypot(moved.x, moved.y);
  std::string message = found.message;
  if (found.found) {
    following_.reset();
    static_cast<void>(localizer_.place(found.pose, odometry, stamp));
  } else if (!found.places.empty() && following.metres < relocalizer_->options().follow_metres) {
    following.places = found.places;
    following.odometry = odometry;
    message += looked_for(found.places.size());
  } else {
    following_.reset();
    message += fmt::format(" (after {} scans over {:.0f} m as the robot drove on)", following.scans,
                           following.metres);
  }
  status_.relocalization = RegistrationStatus::Relocalization{stamp, found.found, message};
  spdlog::info("places followed at t={:.1f}: {} ({:.2f} s)", stamp, message, found.seconds);
}

void LocalizerWorker::search_with_latest_scan(const PoseEstimate& estimate) {
  if (!relocalizer_ || !latest_scan_)
    return;
  const LatestScan& scan = *latest_scan_;
  // The estimate is where the robot is now; the scan was taken where it was then. The odometry since
  // carries the estimate back (nothing, for a robot standing still).
  PoseEstimate at_scan = estimate;
  const std::optional<RobotSnapshot> now = state_.snapshot();
  if (now && scan.odometry) {
    const Pose2 odometry_now{now->sample.odometry.position.x(), now->sample.odometry.position.y(),
                             now->sample.odometry.yaw};
    const Pose2 back =
        Pose2{estimate.x, estimate.y, estimate.yaw}.compose(scan.odometry->relative_to(odometry_now));
    at_scan.x = back.x;
    at_scan.y = back.y;
    at_scan.yaw = back.theta;
  }
  const std::optional<Eigen::Isometry3d> map_from_odom =
      search_around(at_scan, scan.points, scan.odometry, scan.stamp);
  if (map_from_odom)
    state_.set_correction(*map_from_odom, true, scan.stamp);
  state_.set_registration(status_);
}

void LocalizerWorker::process(ScanEvent event) {
  const double cpu_start_ms = thread_cpu_ms();
  const std::optional<Pose3> truth = event.truth;
  std::optional<PoseEstimate> estimate;
  {
    std::lock_guard lock(mutex_);
    estimate = std::exchange(pending_estimate_, std::nullopt);
  }
  PreprocessedScan preprocessed = preprocess(std::move(event));  // step 1, once for the whole pipeline
  const ScanEvent& scan = preprocessed.event;
  const double stamp = scan.stamp;  // `scan` is handed on below
  const std::optional<Pose2> odometry =
      scan.has_odometry ? std::optional<Pose2>(Pose2{scan.odometry.position.x(), scan.odometry.position.y(),
                                                     scan.odometry.yaw})
                        : std::nullopt;
  // The revolution's points as if measured at once, at the stamp: the map and the searches get them so.
  localizer_.deskew(preprocessed.points, preprocessed.times, odometry, stamp);
  preprocessed.times = {};
  if (estimate && relocalizer_)
    static_cast<void>(search_around(*estimate, preprocessed.points, odometry, stamp));
  else if (following_ && relocalizer_ && odometry)
    follow_places(preprocessed.points, *odometry, stamp);
  const LocalizationUpdate update =
      localizer_.add_scan(preprocessed.points, odometry, stamp, scan.sensor_to_base.translation(),
                          scan.gravity, scan.standing_gyro);
  ++status_.scans;
  classify(scan, update);
  if (update.registration) {
    const RegistrationResult& r = *update.registration;
    r.accepted() ? ++status_.accepted : ++status_.rejected;
    if (update.correction == Correction::kPartial)
      ++status_.partial;
    if (update.correction == Correction::kFull)
      ++status_.full;
    status_.last = RegistrationStatus::Last{scan.stamp,
                                            std::string(to_string(r.assessment.verdict)),
                                            std::string(to_string(update.correction)),
                                            std::string(to_string(r.assessment.reason)),
                                            r.assessment.message,
                                            r.rmse,
                                            r.pairs,
                                            r.iterations,
                                            r.seconds};
    if (update.retried) {
      spdlog::info(
          "registration at t={:.1f}: too far from the odometry, found again from the scans' own motion (the "
          "odometry is off: wheels slipping?)",
          scan.stamp);
    }
    if (update.correction == Correction::kNone) {
      ++status_.kept_odometry;
      spdlog::info("registration rejected at t={:.1f}: {}", scan.stamp, r.assessment.message);
    }
  }
  // Lost in a saved map: the robot is looked for everywhere the map's robot drove, at the first lost scan
  // and every few after (RelocalizationOptions::lost_search_every; a search takes 0.1-2.5 s on the scan path:
  // docs/benchmarks.md, "Finding the robot"); found, the next scan starts there; places that fit as well are
  // followed as the robot drives on, as an operator's estimate's are. Not while places are being followed:
  // they are where to look, and the whole map would fit as many places again.
  Eigen::Isometry3d map_from_odom = update.map_from_odom;
  if (relocalizer_ && status_.localization.state == LocalizationState::kLost && !following_) {
    if (lost_scans_++ % relocalizer_->options().lost_search_every == 0) {
      const RelocalizationResult found = relocalizer_->anywhere(preprocessed.points);
      std::string message = "lost: " + found.message;
      if (!found.found && found.places.size() > 1 && odometry) {
        following_ = Following{found.places, *odometry};
        message += looked_for(found.places.size());
      }
      status_.relocalization = RegistrationStatus::Relocalization{stamp, found.found, message};
      if (found.found)
        map_from_odom = localizer_.place(found.pose, odometry, stamp);
      spdlog::info("lost at t={:.1f}, searched the whole map: {} ({} candidates, {:.2f} s)", stamp, message,
                   found.candidates, found.seconds);
    }
  } else {
    lost_scans_ = 0;
  }
  // Kept whatever the mode: a map loaded to localize in is searched with it before the next scan comes.
  latest_scan_ = LatestScan{preprocessed.points, odometry, stamp};
  {
    std::lock_guard lock(mutex_);
    latest_scan_kept_ = true;
  }
  const bool rejected = update.registration && update.correction == Correction::kNone;
  if (sink_ && !rejected) {
    const Eigen::Isometry3d map_from_sensor = update.pose * scan.sensor_to_base;
    sink_(std::move(preprocessed), map_from_sensor);
  }
  // Published after the scan is handed on: whoever sees the count can queue a map command (a save) knowing
  // it runs after this scan is mapped.
  state_.set_gravity_mounting(localizer_.gravity_mounting());
  // A lidar alone's pose between scans is carried on by the velocity of the last ones.
  state_.set_correction(map_from_odom, true, stamp,
                        odometry ? std::nullopt : localizer_.velocity(std::nullopt, stamp));
  status_.graph = localizer_.status();
  if (calibration_ != nullptr)
    status_.imu_calibration = calibration_->imu_calibration();
  state_.set_registration(status_);
  {
    std::lock_guard lock(mutex_);
    ++scans_for_the_graph_;
  }
  graph_wake_.notify_one();
  if (observer_) {
    // A relocalization may have moved the map <- odometry correction after the registration.
    observer_(ScanReport{.stamp = stamp,
                         .pose = map_from_odom * update.map_from_odom.inverse() * update.pose,
                         .truth = truth,
                         .registered = update.registration.has_value(),
                         .correction = update.correction,
                         .state = status_.localization.state,
                         .cpu_ms = thread_cpu_ms() - cpu_start_ms});
  }
}

}  // namespace strata::pipeline

#include "server/pipeline/localizer_worker.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <ctime>
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

/// The preprocessed scan as the localizer takes it: its points and their times move over.
ScanToLocalize to_localize(PreprocessedScan& preprocessed) {
  const ScanEvent& event = preprocessed.event;
  ScanToLocalize scan;
  scan.points = std::move(preprocessed.points);
  scan.times = std::exchange(preprocessed.times, {});
  scan.stamp = event.stamp;
  if (event.has_odometry)
    scan.odometry = Pose2{event.odometry.position.x(), event.odometry.position.y(), event.odometry.yaw};
  scan.sensor_origin = event.sensor_to_base.translation();
  scan.gravity = event.gravity;
  scan.standing_gyro = event.standing_gyro;
  return scan;
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
  status_.graph = localizer_.graph_status();  // the mounting error it starts from, before the first scan
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
      const std::size_t optimizations = localizer_.graph_status().optimizations;
      if (localizer_.close_loops()) {
        const PoseGraphStatus graph = localizer_.graph_status();
        if (graph.optimizations > optimizations) {  // a loop closed; else the keyframes took the heights
          spdlog::info(
              "localization: loop closed at t={:.1f}, the estimate moved {:.2f} m ({} loops over {} "
              "keyframes, optimized in {:.2f} s; the odometry's heading drifts {:.1f} degrees an hour; the "
              "IMU is mounted {:.2f} degrees rolled, {:.2f} pitched)",
              graph.last_loop_stamp, graph.last_correction, graph.loops, graph.keyframes,
              graph.last_optimization_seconds, graph.heading_drift_deg_per_h(),
              graph.gravity_mounting_deg().x(), graph.gravity_mounting_deg().y());
          if (calibration_ != nullptr)
            calibration_->update(graph);
        }
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
  localizer_.localize_in(std::move(map));
  if (localizer_.localizing()) {
    spdlog::info("localizing in the loaded map ({} points, indexed in {:.2f} s): it is not changed", points,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } else {
    spdlog::info("mapping: scans are registered against the recent scans and go into the map");
  }
}

void LocalizerWorker::report(const LocalizationHealth& health, double stamp) {
  if (health.state != status_.localization.state) {  // the log says when it changes, both ways
    const auto log_level = health.state == LocalizationState::kOk ? spdlog::level::info : spdlog::level::warn;
    spdlog::log(log_level, "localization {} at t={:.1f}: {}", to_string(health.state), stamp, health.reason);
  }
  status_.localization = health;
}

void LocalizerWorker::report(const std::vector<RelocalizationReport>& searches) {
  for (const RelocalizationReport& search : searches) {
    status_.relocalization = RegistrationStatus::Relocalization{search.stamp, search.found, search.message};
    switch (search.search) {
      case RelocalizationReport::Search::kHint:
        spdlog::info("pose estimate at t={:.1f}: {} ({} candidates, {:.2f} s)", search.stamp, search.message,
                     search.candidates, search.seconds);
        break;
      case RelocalizationReport::Search::kFollow:
        spdlog::info("places followed at t={:.1f}: {} ({:.2f} s)", search.stamp, search.message,
                     search.seconds);
        break;
      case RelocalizationReport::Search::kWholeMap:
        spdlog::info("lost at t={:.1f}, searched the whole map: {} ({} candidates, {:.2f} s)", search.stamp,
                     search.message, search.candidates, search.seconds);
        break;
      case RelocalizationReport::Search::kCheck:
        spdlog::log(search.found ? spdlog::level::info : spdlog::level::warn,
                    "relocalization at t={:.1f}: {}", search.stamp, search.message);
        break;
    }
  }
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

void LocalizerWorker::search_with_latest_scan(const PoseEstimate& estimate) {
  std::optional<Pose2> odometry_now;
  if (const std::optional<RobotSnapshot> now = state_.snapshot())
    odometry_now =
        Pose2{now->sample.odometry.position.x(), now->sample.odometry.position.y(), now->sample.odometry.yaw};
  const std::optional<LatestScanSearch> search = localizer_.search_with_latest_scan(estimate, odometry_now);
  if (!search)
    return;
  report(search->searches);
  report(search->health, search->stamp);
  if (search->map_from_odom)
    state_.set_correction(*search->map_from_odom, true, search->stamp);
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
  if (estimate)
    localizer_.search_at_next_scan(*estimate);
  PreprocessedScan preprocessed = preprocess(std::move(event));  // step 1, once for the whole pipeline
  ScanToLocalize scan = to_localize(preprocessed);
  const LocalizedScan localized = localizer_.localize(scan);
  report(preprocessed.event, localized);
  {
    std::lock_guard lock(mutex_);
    latest_scan_kept_ = true;
  }
  const double stamp = scan.stamp;
  if (sink_ && localized.mappable()) {
    const Eigen::Isometry3d map_from_sensor = localized.update.pose * preprocessed.event.sensor_to_base;
    preprocessed.points = std::move(scan.points);  // deskewed
    sink_(std::move(preprocessed), map_from_sensor, localized.anchor);
  }
  // Published after the scan is handed on: whoever sees the count can queue a map command (a save) knowing
  // it runs after this scan is mapped. A lidar alone's pose between scans is carried on by its velocity.
  state_.set_gravity_mounting(localizer_.gravity_mounting());
  state_.set_correction(localized.map_from_odom, true, stamp, localized.velocity);
  status_.graph = localizer_.graph_status();
  if (calibration_ != nullptr)
    status_.imu_calibration = calibration_->imu_calibration();
  state_.set_registration(status_);
  {
    std::lock_guard lock(mutex_);
    ++scans_for_the_graph_;
  }
  graph_wake_.notify_one();
  if (observer_) {
    observer_(ScanReport{.stamp = stamp,
                         .pose = localized.pose,
                         .truth = truth,
                         .registered = localized.update.registration.has_value(),
                         .correction = localized.update.correction,
                         .rmse = localized.update.registration ? localized.update.registration->rmse : 0.0,
                         .state = localized.health.state,
                         .cpu_ms = thread_cpu_ms() - cpu_start_ms});
  }
}

void LocalizerWorker::report(const ScanEvent& scan, const LocalizedScan& localized) {
  const LocalizationUpdate& update = localized.update;
  ++status_.scans;
  report(localized.searches);
  report(localized.health, scan.stamp);
  if (!update.registration)
    return;
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

}  // namespace strata::pipeline

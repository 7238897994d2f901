#include "server/pipeline/robot_pipeline.hpp"

#include <numbers>
#include <stdexcept>
#include <utility>

namespace strata::pipeline {
namespace {

TraversabilityConfig traversability_for(const RobotParameters& robot) {
  TraversabilityConfig traversability;
  traversability.max_step = robot.max_step;
  traversability.max_slope = robot.max_slope_deg * std::numbers::pi / 180.0;
  traversability.robot_height = robot.height;
  return traversability;
}

NavigatorConfig navigation_for(const RobotParameters& robot) {
  NavigatorConfig navigation;
  navigation.graph.traversability = traversability_for(robot);
  navigation.graph.robot_radius = robot.radius;
  return navigation;
}

MappingOptions mapping_for(const RobotParameters& robot) {
  MappingOptions mapping;
  mapping.map.traversability = traversability_for(robot);
  return mapping;
}

/// The store for the driver's IMU in `file`; one that keeps nothing for a driver without an IMU.
GraphLocalizerOptions localization_for(const PipelineOptions& options) {
  GraphLocalizerOptions localization;
  if (options.registration_threads)
    localization.scan_matching.registration.icp.threads = *options.registration_threads;
  return localization;
}

ImuCalibrationStore calibration_store(const std::filesystem::path& file, const RobotDriver& driver) {
  const std::optional<std::string> imu = driver.imu_name();
  if (file.empty() || !imu)
    return ImuCalibrationStore();
  return ImuCalibrationStore(file, *imu);
}

}  // namespace

RobotPipeline::RobotPipeline(std::unique_ptr<RobotDriver> driver,
                             std::vector<std::unique_ptr<replay::Recorder>> recorders,
                             const PipelineOptions& options)
    : driver_(std::move(driver)),
      recording_(std::move(recorders)),
      navigator_(navigation_for(options.robot)),
      mapping_(map_state_, options.maps_dir, mapping_for(options.robot)),
      calibration_(calibration_store(options.imu_calibration_file, *driver_)),
      localizer_(robot_state_, localization_for(options), driver_->initial_map_from_odom()),
      max_scans_(options.max_scans),
      initial_map_(options.initial_map),
      initial_map_mode_(options.initial_map_mode) {
  robot_state_.set_driver(DriverStatus{driver_->kind(), false});
  robot_state_.set_sensor_timeout(options.sensor_timeout);
  localizer_.keep_imu_calibration(calibration_);
  take_scans_from_the_driver();
  map_the_registered_scans();
  plan_on_the_live_map();
  drive_the_base_from_the_navigator();
  record_what_the_server_works_out();
}

RobotPipeline::~RobotPipeline() {
  stop();
}

void RobotPipeline::take_scans_from_the_driver() {
  outputs_.on_sample = [this](const RobotSample& sample) {
    robot_state_.publish(sample);
    if (!recording_.empty()) {
      recording_.record(sample);
      const auto path = navigator_.path();
      recording_.record_goal(navigator_.goal_status(), path.get(), sample.stamp);
    }
  };
  outputs_.on_scan = [this](ScanEvent scan) {
    robot_state_.scan_delivered();  // the sensor works, whether or not the pipeline takes the scan
    if (max_scans_ != 0 && scans_taken_ >= max_scans_)
      return;  // --max-scans: a run of a fixed length; the map stays as it is
    ++scans_taken_;
    recording_.record(scan);
    localizer_.submit(std::move(scan));
  };
  // A replay as fast as possible waits for the pipeline instead of dropping scans.
  outputs_.wait_for_pipeline = [this] { return localizer_.flush() && mapping_.flush(); };
  outputs_.on_finished = [this] { robot_state_.set_driver(DriverStatus{driver_->kind(), true}); };
}

void RobotPipeline::map_the_registered_scans() {
  localizer_.set_registered_scan_sink([this](PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                                             const std::optional<KeyframeAnchor>& anchor) {
    mapping_.submit(std::move(scan), map_from_sensor, anchor);
  });
  // The map follows the pose graph: rebuilt from the keyframes when a loop closure moved them. A goal
  // the old map refuses meanwhile waits for the rebuilt one.
  localizer_.set_keyframes_moved_sink([this](const std::vector<KeyframePose>& keyframes) {
    navigator_.map_rebuilding(true);
    mapping_.rebuild_from(keyframes);
    navigator_.map_rebuilding(false);
  });
  // A saved map keeps the keyframes, and a map loaded for localizing is what the scans register against
  // from then on (docs/architecture.md 4.1, "Localizing in a saved map").
  mapping_.set_keyframe_source([this] { return localizer_.keyframes(); });
  mapping_.on_map_loaded(
      [this](std::shared_ptr<const LocalizationMap> map) { localizer_.localize_in(std::move(map)); });
}

void RobotPipeline::plan_on_the_live_map() {
  // The navigator copies the map's surfaces after every change.
  mapping_.add_listener(navigator_.map_listener());
}

void RobotPipeline::drive_the_base_from_the_navigator() {
  // Until an operator sends a goal or teleop the navigator has nothing to say and the simulator drives
  // its demo route. It steers by the localized pose once there is one.
  driver_->set_command_source([this](const RobotSample& sample) -> std::optional<VelocityCommand> {
    const auto snapshot = robot_state_.snapshot();
    const auto command = navigator_.drive(snapshot ? snapshot->estimate : sample.odometry, sample.stamp);
    if (!command)
      return std::nullopt;
    return VelocityCommand{.v = command->v, .w = command->w, .by_hand = command->by_hand};
  });
}

void RobotPipeline::record_what_the_server_works_out() {
  localizer_.set_scan_observer([this](const LocalizerWorker::ScanReport& report) {
    if (!recording_.empty()) {
      // The correction as the robot state holds it after the scan: the estimate over the odometry.
      const auto snapshot = robot_state_.snapshot();
      const Eigen::Isometry3d map_from_odom =
          snapshot ? snapshot->estimate.to_isometry() * snapshot->sample.odometry.to_isometry().inverse()
                   : Eigen::Isometry3d::Identity();
      recording_.record_pose(report.stamp, report.pose, map_from_odom);
    }
    if (scan_observer_)
      scan_observer_(report);
  });
  mapping_.add_listener([this](const MapUpdate& update) { recording_.record_map(update); });
}

void RobotPipeline::on_map_published(std::function<void()> callback) {
  mapping_.on_published(std::move(callback));
}

void RobotPipeline::start() {
  if (started_)
    return;
  started_ = true;
  mapping_.start();
  if (!initial_map_.empty()) {
    const CommandResult loaded = mapping_.load_map(initial_map_, initial_map_mode_);
    if (!loaded.ok)
      throw std::runtime_error("cannot load the map '" + initial_map_ + "': " + loaded.message);
  }
  localizer_.start();
  navigator_.start();
  driver_->start(std::move(outputs_));
}

void RobotPipeline::stop() {
  if (stopped_)
    return;
  stopped_ = true;
  driver_->stop();  // first: its thread calls into everything below
  navigator_.stop();
  localizer_.stop();
  mapping_.stop();
  recording_.stop();  // last, when nothing records any more: writes what is queued, finishes each file
}

ServerServices RobotPipeline::services() {
  ServerServices services;
  services.robot = &robot_state_;
  services.map = &map_state_;
  services.motion = &navigator_;
  services.maps = &mapping_;
  services.localization = &localizer_;
  services.calibration = &calibration_;
  services.sim_world = driver_->world();  // null for a replay or a lidar: no simulated world to draw
  return services;
}

}  // namespace strata::pipeline

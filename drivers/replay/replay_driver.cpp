#include "drivers/replay/replay_driver.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace strata::replay {
namespace {

/// The pipeline takes planar wheel odometry (x, y, heading: ScanToMapLocalizer::add_scan); a dataset's
/// 6-DoF odometry is projected onto the ground so that the pose the server publishes (the correction applied
/// to this odometry) is the one the localizer computed. The simulator's odometry is planar already.
Pose3 planar(const Pose3& pose) {
  return Pose3::from_pose2(Pose2{pose.position.x(), pose.position.y(), pose.yaw});
}

}  // namespace

ReplayDriver::ReplayDriver(Dataset dataset, ReplayOptions options)
    : dataset_(std::move(dataset)), options_(options), clock_(options_.pacing) {
  const bool mount_unknown = std::any_of(dataset_.scans.begin(), dataset_.scans.end(),
                                         [](const DatasetScan& s) { return !s.mount_known; });
  if (options_.mount || mount_unknown)
    mount_.emplace(options_.mount, "replay");
  if (mount_unknown)
    carry_references_to_the_base();
  const auto& scans = dataset_.scans;
  const bool has_odometry =
      std::all_of(scans.begin(), scans.end(), [](const DatasetScan& s) { return s.odometry.has_value(); });
  const bool has_reference =
      std::all_of(scans.begin(), scans.end(), [](const DatasetScan& s) { return s.reference.has_value(); });
  OdometrySource source = options_.odometry;
  if (source == OdometrySource::kAuto) {
    source = has_odometry    ? OdometrySource::kDataset
             : has_reference ? OdometrySource::kReference
                             : OdometrySource::kNone;
  }
  if (source == OdometrySource::kDataset && !has_odometry)
    throw DatasetError(dataset_.directory.string() +
                       ": the dataset has no odometry for every scan (try the reference poses)");
  if (source == OdometrySource::kReference && !has_reference)
    throw DatasetError(dataset_.directory.string() + ": the dataset has no reference pose for every scan");

  std::vector<Pose3> odometry;
  if (source == OdometrySource::kNone) {
    // A plain list of scans (or one replayed as if by a lidar alone): the pipeline predicts the motion
    // from the scans themselves, as it does for a pcap or a live lidar.
    odometry.assign(scans.size(), Pose3{});
    has_odometry_ = false;
    odometry_from_ = "none (the scans' own motion)";
  } else if (source == OdometrySource::kReference) {
    std::vector<Pose3> reference;
    for (const DatasetScan& scan : scans)
      reference.push_back(*scan.reference);
    odometry = odometry_from_reference(reference, options_.noise, options_.seed);
    odometry_from_ =
        options_.noise.none()
            ? std::string("reference poses")
            : fmt::format("reference poses with noise {:.3g} m/m, {:.3g} deg/m, seed {}",
                          options_.noise.translation, options_.noise.rotation * 180.0 / M_PI, options_.seed);
  } else {
    for (const DatasetScan& scan : scans)
      odometry.push_back(planar(*scan.odometry));
    odometry_from_ = "the dataset";
  }

  // The map frame: as recorded; else the reference's frame, so that estimates and reference compare;
  // else where the odometry starts. (Without odometry, the constant odometry is the first scan's pose.)
  if (dataset_.initial_map_from_odom && source == OdometrySource::kDataset)
    initial_map_from_odom_ = *dataset_.initial_map_from_odom;
  else if (has_reference)
    initial_map_from_odom_ =
        scans.front().reference->to_isometry() * odometry.front().to_isometry().inverse();

  const auto sample_of = [](double stamp, const Pose3& pose, const std::optional<Pose3>& reference) {
    RobotSample sample;
    sample.stamp = stamp;
    sample.odometry = pose;
    sample.truth = reference.value_or(pose);  // shown as "truth": the reference when there is one
    return sample;
  };
  // The odometry stream of a recording goes out between the scans; other datasets only have the scans'.
  if (source == OdometrySource::kDataset) {
    for (const DatasetOdometry& sample : dataset_.odometry)
      events_.push_back(Event{sample.stamp, std::nullopt,
                              sample_of(sample.stamp, planar(sample.odometry), sample.reference)});
  }
  for (std::size_t i = 0; i < scans.size(); ++i)
    events_.push_back(Event{scans[i].stamp, i, sample_of(scans[i].stamp, odometry[i], scans[i].reference)});
  // By time; at equal stamps, the odometry sample before the scan (as the simulator hands them on).
  std::stable_sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
    if (a.stamp != b.stamp)
      return a.stamp < b.stamp;
    return !a.scan.has_value() && b.scan.has_value();
  });
}

ReplayDriver::~ReplayDriver() {
  stop();
}

std::string ReplayDriver::description() const {
  return fmt::format("{} from {}, odometry from {}, {}", dataset_.description, dataset_.directory.string(),
                     odometry_from_, clock_.description());
}

std::optional<std::string> ReplayDriver::imu_name() const {
  const bool has_imu =
      std::ranges::any_of(dataset_.scans, [](const DatasetScan& scan) { return scan.gravity.has_value(); });
  if (!has_imu)
    return std::nullopt;
  std::error_code error;
  const std::filesystem::path directory = std::filesystem::weakly_canonical(dataset_.directory, error);
  return "the IMU of the dataset " + (error ? dataset_.directory : directory).string();
}

void ReplayDriver::start(Outputs outputs) {
  if (thread_.joinable())
    return;
  thread_ = std::thread([this, outputs = std::move(outputs)]() mutable { run(std::move(outputs)); });
}

void ReplayDriver::stop() {
  clock_.stop();
  if (thread_.joinable())
    thread_.join();
}

void ReplayDriver::carry_references_to_the_base() {
  // The mount now, given or from the ground in the first scans, so that the map frame is the reference's
  // from the first scan on (SensorMount::apply then hands every scan the same mount).
  std::optional<Eigen::Isometry3d> sensor_to_base = mount_->mount();
  for (std::size_t i = 0; !sensor_to_base && i < std::min(dataset_.scans.size(), SensorMount::kScansToTry);
       ++i) {
    ScanEvent probe;
    try {
      probe.points = load_points(dataset_.scans[i]);
    } catch (const std::exception&) {
      continue;  // skipped with a message when it is played
    }
    mount_->apply(probe);
    sensor_to_base = mount_->mount();
  }
  if (!sensor_to_base)
    return;  // no ground: the sensor's frame is the base's, and so are the references
  const Eigen::Isometry3d sensor_from_base = sensor_to_base->inverse();
  const auto carried = [&](std::optional<Pose3>& reference) {
    if (reference)
      reference = Pose3::from_isometry(reference->to_isometry() * sensor_from_base);
  };
  for (DatasetScan& scan : dataset_.scans)
    carried(scan.reference);
  for (DatasetOdometry& sample : dataset_.odometry)
    carried(sample.reference);
}

void ReplayDriver::run(Outputs outputs) {
  std::size_t played = 0;
  for (const Event& event : events_) {
    if (clock_.stopped())
      return;
    std::optional<ScanEvent> scan;
    if (event.scan) {
      // Read before waiting for the scan's time, so a slow file does not delay it.
      const DatasetScan& source = dataset_.scans[*event.scan];
      try {
        scan.emplace();
        scan->points = load_points(source, &scan->point_times);
      } catch (const std::exception& error) {
        spdlog::error("replay: skipping scan {}: {}", *event.scan, error.what());
        ++failed_;
        scan.reset();
      }
      if (scan) {
        scan->stamp = source.stamp;
        scan->duration = source.duration;
        scan->sensor = source.sensor;
        scan->sensor_to_base = source.sensor_to_base;
        if (mount_)
          mount_->apply(*scan);
        scan->gravity = source.gravity;
        scan->standing_gyro = source.standing_gyro;
        scan->odometry = event.sample.odometry;
        scan->has_odometry = has_odometry_;
        scan->truth = source.reference;
        scan->rays = source.rays != 0 ? source.rays : scan->points.size();
        scan->max_range = source.max_range;
      }
    }
    if (!clock_.wait_until_due(event.stamp))
      return;
    outputs.on_sample(event.sample);
    if (scan) {
      outputs.on_scan(std::move(*scan));
      ++played;
      if (!clock_.wait_for_pipeline(outputs.wait_for_pipeline))
        return;
    }
  }
  finished_ = true;
  if (outputs.on_finished)
    outputs.on_finished();
  spdlog::info("replay finished: {} scans played in {:.1f} s ({} unreadable); serving the map", played,
               clock_.seconds_playing(), failed_.load());
}

}  // namespace strata::replay

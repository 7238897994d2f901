#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "core/geometry/pose.hpp"
#include "core/localization/localization_health.hpp"
#include "core/localization/pose_extrapolator.hpp"
#include "core/localization/pose_graph_status.hpp"
#include "drivers/robot_sample.hpp"
#include "server/state/sensor_watch.hpp"

namespace strata {

/// The IMU calibration the server keeps between runs of the same robot (pipeline::ImuCalibrationStore;
/// docs/architecture.md 4.1, "IMU calibration kept between runs").
struct ImuCalibrationStatus {
  enum class Kept {
    kOff,     ///< nothing is kept: the base has no IMU, or --no-imu-calibration
    kNone,    ///< nothing kept for this IMU yet
    kLoaded,  ///< this run started from what an earlier run kept
    kSaved,   ///< this run's own estimate, confirmed by loop closures, is kept for the next
  };
  Kept kept = Kept::kOff;
  std::string imu;  ///< which IMU (RobotDriver::imu_name); empty when off
  /// The kept mounting error's roll and pitch, degrees; with kLoaded and kSaved.
  std::optional<Eigen::Vector2d> mounting_deg;
  std::size_t loops = 0;  ///< loop closures the kept estimate was confirmed by
};
[[nodiscard]] inline const char* to_string(ImuCalibrationStatus::Kept kept) {
  switch (kept) {
    case ImuCalibrationStatus::Kept::kNone:
      return "none";
    case ImuCalibrationStatus::Kept::kLoaded:
      return "loaded";
    case ImuCalibrationStatus::Kept::kSaved:
      return "saved";
    case ImuCalibrationStatus::Kept::kOff:
      break;
  }
  return "off";
}

/// How scan registration has been going: what the status stream reports.
struct RegistrationStatus {
  std::size_t scans = 0;     ///< scans the localizer processed
  std::size_t accepted = 0;  ///< registrations fault control accepted
  std::size_t rejected = 0;  ///< registrations it rejected (the odometry guess was kept)
  std::size_t partial = 0;   ///< corrections that took odometry along an unconstrained direction
  std::size_t dropped = 0;   ///< scans skipped because the localizer was still busy
  /// Registrations not used at all (the odometry guess kept): what "rejected" means to a user. A
  /// rejected verdict may still correct partly (degenerate geometry: `partial`).
  std::size_t kept_odometry = 0;
  std::size_t full = 0;  ///< registrations used whole
  struct Last {
    double stamp = 0.0;
    std::string verdict;     ///< "accepted" or "rejected" (fault control's)
    std::string correction;  ///< what was used: "full", "partial" (odometry along a corridor), "none"
    std::string reason;      ///< why rejected ("degenerate_geometry", ...), "none" when accepted
    std::string message;
    double rmse = 0.0;
    std::size_t pairs = 0;
    int iterations = 0;
    double seconds = 0.0;
  };
  std::optional<Last> last;
  PoseGraphStatus graph;  ///< keyframes and loop closures (docs/architecture.md 4.1)
  ImuCalibrationStatus imu_calibration;
  /// The last search for the robot in a saved map (an operator's pose estimate).
  struct Relocalization {
    double stamp = 0.0;  ///< of the scan it searched with
    bool found = false;
    std::string message;
  };
  std::optional<Relocalization> relocalization;
  /// ok, degraded or lost, and why in plain words (docs/architecture.md 4.1, "Localization state").
  LocalizationHealth localization = LocalizationHealth::no_scan_yet();
};

/// Where the scans come from (the driver), for the status stream.
struct DriverStatus {
  std::string kind = "simulator";  ///< "simulator" or "replay"
  bool finished = false;           ///< a replay handed on all its scans
};

/// The robot's live state at one instant: the driver's sample and the localized estimate.
struct RobotSnapshot {
  RobotSample sample;
  Pose3 estimate;          ///< odometry carried into the map by the latest correction (PoseExtrapolator)
  bool localized = false;  ///< at least one scan registered: the estimate is no longer bare odometry
  /// Counts every new sample and every new correction: a snapshot with a higher one says something new,
  /// even at the same sample stamp (a lidar alone's scan registered after its sample went out).
  std::uint64_t version = 0;
};

/// The latest robot state, written by the driver thread and the localizer, read by the network side.
/// Plain mutex-protected copies: the data is small and readers want the newest, never a history.
class RobotState {
 public:
  void publish(const RobotSample& sample) {
    const auto now = SensorWatch::Clock::now();
    std::lock_guard lock(mutex_);
    latest_ = sample;
    ++version_;
    extrapolator_.add_sample(sample.stamp, sample.odometry, sample.gravity);
    sensor_.sample(sample.awaiting_scan, now);
  }
  /// The driver delivered a scan (whether or not the pipeline takes it).
  void scan_delivered() {
    const auto now = SensorWatch::Clock::now();
    std::lock_guard lock(mutex_);
    sensor_.scan(now);
  }
  /// Seconds a due scan may be waited for before the sensor counts as stalled.
  void set_sensor_timeout(double seconds) {
    std::lock_guard lock(mutex_);
    sensor_.set_timeout(seconds);
  }
  /// The localizer's correction, computed from the scan taken at `scan_stamp` (none: a given start); for a
  /// base without odometry, with its velocity from the last scans (PoseExtrapolator::set_velocity).
  void set_correction(const Eigen::Isometry3d& map_from_odom, bool localized,
                      std::optional<double> scan_stamp = std::nullopt,
                      const std::optional<Pose2>& velocity = std::nullopt) {
    std::lock_guard lock(mutex_);
    extrapolator_.set_correction(map_from_odom, scan_stamp);
    extrapolator_.set_velocity(velocity);
    localized_ = localized;
    ++version_;
  }
  /// The gravity reading's mounting error the localizer has learnt (PoseExtrapolator::set_mounting_error).
  void set_gravity_mounting(const Eigen::Vector3d& mounting) {
    std::lock_guard lock(mutex_);
    extrapolator_.set_mounting_error(mounting);
  }
  void set_registration(const RegistrationStatus& status) {
    std::lock_guard lock(mutex_);
    registration_ = status;
  }

  void set_driver(const DriverStatus& driver) {
    std::lock_guard lock(mutex_);
    driver_ = driver;
    if (driver.finished)
      sensor_.finished();
  }

  [[nodiscard]] std::optional<RobotSnapshot> snapshot() const {
    std::lock_guard lock(mutex_);
    if (!latest_)
      return std::nullopt;
    RobotSnapshot snapshot{*latest_, {}, localized_, version_};
    snapshot.estimate = extrapolator_.estimate();
    return snapshot;
  }
  [[nodiscard]] RegistrationStatus registration() const {
    std::lock_guard lock(mutex_);
    return registration_;
  }
  [[nodiscard]] DriverStatus driver() const {
    std::lock_guard lock(mutex_);
    return driver_;
  }
  [[nodiscard]] SensorStatus sensor() const {
    const auto now = SensorWatch::Clock::now();
    std::lock_guard lock(mutex_);
    return sensor_.status(now);
  }

 private:
  mutable std::mutex mutex_;
  std::optional<RobotSample> latest_;
  std::uint64_t version_ = 0;  // RobotSnapshot::version
  PoseExtrapolator extrapolator_;
  bool localized_ = false;
  RegistrationStatus registration_;
  DriverStatus driver_;
  SensorWatch sensor_;
};

}  // namespace strata

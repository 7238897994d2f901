#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "drivers/playback_clock.hpp"
#include "drivers/replay/dataset.hpp"
#include "drivers/replay/reference_odometry.hpp"
#include "drivers/robot_driver.hpp"
#include "drivers/sensor_mount.hpp"

namespace strata::replay {

/// Where a replay's odometry comes from.
enum class OdometrySource {
  kAuto,       ///< the dataset's odometry when it has one, else its reference poses, else none
  kDataset,    ///< the dataset's odometry (3DTK .pose, a recording's odometry.csv)
  kReference,  ///< made from the reference poses (KITTI poses.txt, 3DTK .frames, a recording's truth), with
               ///< noise
  kNone,       ///< none: a lidar alone (ScanEvent::has_odometry false), its motion predicted from its scans;
               ///< reference poses, where there are any, are only shown as the truth
};

struct ReplayOptions {
  /// By the dataset's clock (times a time scale), or each scan as soon as the pipeline has finished the one
  /// before (none dropped), odometry without waiting.
  PlaybackPacing pacing;
  OdometrySource odometry = OdometrySource::kAuto;
  OdometryNoise noise;     ///< only for odometry made from reference poses
  std::uint64_t seed = 1;  ///< of the noise
  /// The sensor on the base for every scan (--lidar-mount), in place of the dataset's; where neither says,
  /// it is estimated from the ground (SensorMount).
  std::optional<Eigen::Isometry3d> mount;
};

/// Plays a dataset (open_dataset) through the RobotDriver seam on its own thread: odometry samples and scans
/// in the dataset's time order, paced by its clock or as fast as the pipeline takes them. It cannot move:
/// velocity commands are ignored. When everything is played it stops, and finished() turns true; the
/// server keeps serving the map.
class ReplayDriver final : public RobotDriver {
 public:
  /// Throws DatasetError when the odometry asked for is not in the dataset.
  ReplayDriver(Dataset dataset, ReplayOptions options);
  ~ReplayDriver() override;

  [[nodiscard]] std::string kind() const override { return "replay"; }
  [[nodiscard]] std::string description() const override;
  [[nodiscard]] Eigen::Isometry3d initial_map_from_odom() const override { return initial_map_from_odom_; }
  /// A dataset with gravity readings: its IMU, named by the dataset's directory.
  [[nodiscard]] std::optional<std::string> imu_name() const override;
  void start(Outputs outputs) override;
  void stop() override;
  [[nodiscard]] bool finished() const override { return finished_; }
  /// Scans whose points could not be read (logged and skipped).
  [[nodiscard]] std::size_t failed_scans() const { return failed_; }

 private:
  /// One thing to play: an odometry sample, or a scan (whose odometry sample goes out first).
  struct Event {
    double stamp = 0.0;
    std::optional<std::size_t> scan;  ///< index into scans_, else an odometry sample
    RobotSample sample;
  };
  void run(Outputs outputs);
  /// A dataset that does not say where its sensor sits has the sensor's reference poses (nothing knew a
  /// base): carried into the base frame through the mount (given, or estimated now from the first scans),
  /// so that the map frame, the estimates and the truth shown compare. docs/lidar.md.
  void carry_references_to_the_base();

  Dataset dataset_;
  ReplayOptions options_;
  std::string odometry_from_;
  bool has_odometry_ = true;          ///< false when the scans are handed on as a lidar alone's (kNone)
  std::optional<SensorMount> mount_;  ///< when --lidar-mount is given or the dataset has no mount
  std::vector<Event> events_;
  Eigen::Isometry3d initial_map_from_odom_ = Eigen::Isometry3d::Identity();
  PlaybackClock clock_;
  std::atomic<bool> finished_{false};
  std::atomic<std::size_t> failed_{0};
  std::thread thread_;
};

}  // namespace strata::replay

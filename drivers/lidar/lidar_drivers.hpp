#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/pcap_scan_source.hpp"
#include "drivers/lidar/udp_scan_source.hpp"
#include "drivers/playback_clock.hpp"
#include "drivers/robot_driver.hpp"
#include "drivers/sensor_mount.hpp"

namespace strata::lidar {

/// A lidar alone has no wheel odometry: both drivers hand on scans without (ScanEvent::has_odometry
/// false), and the localizer predicts each from the motion between the scans before it.
struct LidarDriverOptions {
  LidarSetup setup;
  /// The sensor's mounting on the base (--lidar-mount): where the map puts the ground relative to it.
  /// Nothing: estimated from the ground under the sensor in the first scans (SensorMount).
  std::optional<Eigen::Isometry3d> sensor_to_base;
};

/// Plays a packet capture (strata serve --pcap FILE --lidar MODEL): its revolutions as scans, paced by the
/// capture clock (times a time scale) or as fast as the pipeline takes them, then finished() (like a
/// replay). Logs the decoder's counters once at the end.
class PcapLidarDriver final : public RobotDriver {
 public:
  /// Opens the capture and reads the calibration: throws PcapError or LidarConfigError (and
  /// std::invalid_argument for a time scale that is not positive).
  PcapLidarDriver(std::filesystem::path pcap, LidarDriverOptions options, PlaybackPacing pacing);
  ~PcapLidarDriver() override;

  [[nodiscard]] std::string kind() const override { return "pcap"; }
  [[nodiscard]] std::string description() const override;
  [[nodiscard]] Eigen::Isometry3d initial_map_from_odom() const override {
    return Eigen::Isometry3d::Identity();
  }
  void start(Outputs outputs) override;
  void stop() override;
  [[nodiscard]] bool finished() const override { return finished_; }

 private:
  void run(Outputs outputs);

  std::filesystem::path pcap_;
  LidarDriverOptions options_;
  SensorMount mount_;
  PlaybackClock clock_;
  PcapScanSource source_;
  std::atomic<bool> finished_{false};
  std::thread thread_;
};

/// A live lidar (strata serve --lidar MODEL without --pcap): its UDP packets on --lidar-address /
/// --lidar-port, revolutions handed on as they complete, stamped with the host's receive time. Never
/// finished. Logs the decoder's counters every `counters_period`.
class LiveLidarDriver final : public RobotDriver {
 public:
  /// Reads the calibration and binds the socket: throws LidarConfigError or boost::system::system_error.
  LiveLidarDriver(LidarDriverOptions options, const std::string& address,
                  std::chrono::seconds counters_period = std::chrono::seconds(60));
  ~LiveLidarDriver() override;

  [[nodiscard]] std::string kind() const override { return "lidar"; }
  [[nodiscard]] std::string description() const override;
  [[nodiscard]] Eigen::Isometry3d initial_map_from_odom() const override {
    return Eigen::Isometry3d::Identity();
  }
  void start(Outputs outputs) override;
  void stop() override;

 private:
  void schedule_counters();

  LidarDriverOptions options_;
  SensorMount mount_;  // on the io thread
  std::string address_;
  std::chrono::seconds counters_period_;
  boost::asio::io_context io_;
  UdpScanSource source_;
  boost::asio::steady_timer counters_timer_;
  std::size_t scans_ = 0;  // on the io thread
  std::thread thread_;
};

/// One log line of a decoder's counters: packets, skipped, model mismatch, revolutions (complete, partial).
[[nodiscard]] std::string describe_counters(const LidarScanBuilder& builder);

}  // namespace strata::lidar

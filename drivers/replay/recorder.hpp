#pragma once

#include <Eigen/Geometry>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <utility>
#include <variant>

#include "drivers/robot_sample.hpp"
#include "drivers/scan_event.hpp"

namespace strata::replay {

/// What the recorder has done: for the log at the end, and tests.
struct RecorderStatus {
  std::size_t scans = 0;    ///< scan files written and listed
  std::size_t samples = 0;  ///< odometry rows written
  std::size_t dropped = 0;  ///< scans or samples dropped because the disk fell behind (queue full)
  std::size_t errors = 0;   ///< writes that failed (logged)
};

/// Writes the scans and odometry a server receives into Strata's recording layout (recording_layout.hpp),
/// so the run can be replayed exactly (`strata serve --replay DIR`). The driver's thread only queues: the
/// files are written on the recorder's own thread, and when the disk falls behind the bounded queue drops
/// (and counts) rather than stalling the robot. A failed write is logged and counted, never thrown.
class Recorder {
 public:
  struct Limits {
    std::size_t queued_scans = 16;        ///< scans waiting to be written
    std::size_t queued_samples = 100000;  ///< odometry samples waiting (about 17 min at 100 Hz)
  };

  /// Creates `directory` (and scans/) and writes recording.json with `metadata` (source, seed, ...) and the
  /// initial pose. Throws std::runtime_error when the directory cannot be made or already holds a recording.
  Recorder(std::filesystem::path directory, const nlohmann::json& metadata,
           const Eigen::Isometry3d& initial_map_from_odom, Limits limits);
  Recorder(std::filesystem::path directory, const nlohmann::json& metadata,
           const Eigen::Isometry3d& initial_map_from_odom)
      : Recorder(std::move(directory), metadata, initial_map_from_odom, Limits{}) {}
  /// Writes what is queued, then completes recording.json.
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// From the driver's thread; return at once.
  void record(const RobotSample& sample);
  void record(const ScanEvent& scan);
  /// Waits until everything queued so far is written (tests, shutdown).
  void flush();
  [[nodiscard]] RecorderStatus status() const;
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }

 private:
  using Item = std::variant<RobotSample, ScanEvent>;
  void run();
  void write(const Item& item);
  void write_metadata(bool finished);

  std::filesystem::path directory_;
  nlohmann::json metadata_;
  Limits limits_;
  std::ofstream scans_csv_;         // recorder thread only
  std::ofstream odometry_csv_;      // recorder thread only
  std::size_t next_scan_file_ = 0;  // recorder thread only
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable drained_;
  std::deque<Item> queue_;
  std::size_t queued_scans_ = 0;
  std::size_t queued_samples_ = 0;
  bool writing_ = false;
  bool stopping_ = false;
  RecorderStatus status_;
  std::thread thread_;
};

}  // namespace strata::replay

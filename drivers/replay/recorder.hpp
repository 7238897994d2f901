#pragma once

#include <Eigen/Geometry>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <utility>
#include <variant>

#include "drivers/replay/recording_writer.hpp"

namespace strata::replay {

/// Writes the scans and odometry a server receives through a RecordingWriter: Strata's recording layout
/// (LayoutWriter, `--record DIR`) or an MCAP file of ROS 2 messages (McapRecordingWriter, `--record-mcap`),
/// so the run can be replayed exactly (`strata serve --replay`). The driver's thread only queues: the
/// files are written on the recorder's own thread, and when the disk falls behind the bounded queue drops
/// (and counts) rather than stalling the robot. A failed write is logged and counted, never thrown.
class Recorder {
 public:
  struct Limits {
    std::size_t queued_scans = 16;        ///< scans waiting to be written
    std::size_t queued_samples = 100000;  ///< odometry samples waiting (about 17 min at 100 Hz)
  };

  Recorder(std::unique_ptr<RecordingWriter> writer, Limits limits);
  /// Into Strata's recording layout (LayoutWriter: throws std::runtime_error when the directory cannot be
  /// made or already holds a recording).
  Recorder(std::filesystem::path directory, const nlohmann::json& metadata,
           const Eigen::Isometry3d& initial_map_from_odom, Limits limits);
  Recorder(std::filesystem::path directory, const nlohmann::json& metadata,
           const Eigen::Isometry3d& initial_map_from_odom)
      : Recorder(std::move(directory), metadata, initial_map_from_odom, Limits{}) {}
  /// Writes what is queued, then finishes the writer (recording.json completed, the MCAP file closed).
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// From the driver's thread; return at once.
  void record(const RobotSample& sample);
  void record(const ScanEvent& scan);
  /// What the server worked out (pose, path, goal events, map): dropped, not counted, when the queue is full.
  void record(TopicMessage message);
  /// Waits until everything queued so far is written (tests, shutdown).
  void flush();
  [[nodiscard]] RecorderStatus status() const;
  [[nodiscard]] std::string where() const { return writer_->where(); }

 private:
  using Item = std::variant<RobotSample, ScanEvent, TopicMessage>;
  void run();
  void write(const Item& item);

  std::unique_ptr<RecordingWriter> writer_;  // recorder thread only (after the constructor)
  Limits limits_;
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

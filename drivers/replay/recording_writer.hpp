#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/robot_sample.hpp"
#include "drivers/scan_event.hpp"

namespace strata::replay {

/// What the recorder has done: for the log at the end, and tests.
struct RecorderStatus {
  std::size_t scans = 0;     ///< scan files written and listed
  std::size_t samples = 0;   ///< odometry rows written
  std::size_t messages = 0;  ///< other messages written (an MCAP recording's pose, path, goals, map)
  std::size_t dropped = 0;   ///< scans or samples dropped because the disk fell behind (queue full)
  std::size_t errors = 0;    ///< writes that failed (logged)
};

/// Something the server worked out during the run, as a ROS 2 message (CDR, drivers/ros2) on a topic: the
/// localized pose, the planned path, a goal event, the drivable map. Recorded where the format carries it
/// (an MCAP recording); a replay does not need it.
struct TopicMessage {
  std::string topic;      ///< "/pose"
  std::string_view type;  ///< "geometry_msgs/msg/PoseWithCovarianceStamped" (a message's kType)
  double stamp = 0.0;     ///< robot seconds
  std::vector<std::uint8_t> cdr;
};

/// One recording format, written on the recorder's thread (Recorder): everything a replay needs, the
/// samples and the scans, and what else the format carries. Throws on a failed write (the recorder counts
/// and logs it).
class RecordingWriter {
 public:
  virtual ~RecordingWriter() = default;
  virtual void write(const RobotSample& sample) = 0;
  virtual void write(const ScanEvent& scan) = 0;
  virtual void write(const TopicMessage& /*message*/) {}
  /// Whether write(TopicMessage) keeps them (else the recorder does not queue them).
  [[nodiscard]] virtual bool keeps_topic_messages() const { return false; }
  /// The clean end of the run, with the recorder's counts.
  virtual void finish(const RecorderStatus& status) = 0;
  /// Where it writes, for the log.
  [[nodiscard]] virtual std::string where() const = 0;
};

}  // namespace strata::replay

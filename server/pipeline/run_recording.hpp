#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/mls/drivable_map.hpp"
#include "drivers/replay/recorder.hpp"
#include "server/pipeline/map_update.hpp"
#include "server/state/goal_state.hpp"

namespace strata::pipeline {

/// The run's recorders (--record DIR, --record-mcap FILE) and what the server works out during the run as
/// ROS 2 messages for those formats that carry it (an MCAP recording): the localized pose (/pose and /tf
/// map -> odom), the planned path (/plan), goal events (/goal_events, JSON in std_msgs/String) and the
/// drivable map over the whole map as it changes, the PGM/YAML export's (/map, at most once a second of
/// robot time, and the last one at stop()).
/// The record methods are called from the driver's, the localizer's and the mapping thread; the recorders
/// queue and write on their own threads.
class RunRecording {
 public:
  /// The map is recorded at most this often (robot seconds): a lidar's map changes ten times a second.
  static constexpr double kMapPeriod = 1.0;

  explicit RunRecording(std::vector<std::unique_ptr<replay::Recorder>> recorders);
  [[nodiscard]] bool empty() const { return recorders_.empty(); }

  void record(const RobotSample& sample);
  void record(const ScanEvent& scan);
  /// The base's pose in the map after the scan at `stamp`, with the odometry's correction.
  void record_pose(double stamp, const Eigen::Isometry3d& map_from_base,
                   const Eigen::Isometry3d& map_from_odom);
  /// When the goal's phase or the path's version differs from the last recorded (robot time `stamp`).
  void record_goal(const GoalStatus& goal, const PlannedPath* path, double stamp);
  /// The drivable map over the whole map after a change (mapping thread): made only when it is recorded.
  void record_map(const MapUpdate& update);
  /// Records the map kept back by the period, then writes and closes every recording.
  void stop();

 private:
  void record(const replay::TopicMessage& message);
  void record_grid(const std::shared_ptr<const DrivableMap>& drivable, double stamp);

  std::vector<std::unique_ptr<replay::Recorder>> recorders_;
  std::mutex mutex_;
  double latest_stamp_ = 0.0;                                     // robot time of the latest sample
  std::optional<double> map_recorded_at_;                         // robot time of the last /map recorded
  std::function<std::shared_ptr<const DrivableMap>()> held_map_;  // a newer map not recorded yet
  std::uint64_t goal_id_ = 0;
  std::optional<GoalPhase> goal_phase_;
  std::uint64_t path_version_ = 0, path_goal_ = 0;
};

}  // namespace strata::pipeline

#include "server/pipeline/run_recording.hpp"

#include <nlohmann/json.hpp>
#include <utility>

#include "drivers/replay/mcap_recording_layout.hpp"
#include "drivers/ros2/map_messages.hpp"
#include "drivers/ros2/message_encoding.hpp"

namespace strata::pipeline {
namespace {

ros2::Header header(double stamp, std::string_view frame) {
  return {ros2::Time::from_nanoseconds(stamp > 0.0 ? static_cast<std::uint64_t>(stamp * 1e9) : 0),
          std::string(frame)};
}

}  // namespace

RunRecording::RunRecording(std::vector<std::unique_ptr<replay::Recorder>> recorders)
    : recorders_(std::move(recorders)) {}

void RunRecording::record(const RobotSample& sample) {
  {
    std::lock_guard lock(mutex_);
    latest_stamp_ = sample.stamp;
  }
  for (const auto& recorder : recorders_)
    recorder->record(sample);
}

void RunRecording::record(const ScanEvent& scan) {
  for (const auto& recorder : recorders_)
    recorder->record(scan);
}

void RunRecording::record(const replay::TopicMessage& message) {
  for (const auto& recorder : recorders_)
    recorder->record(message);
}

void RunRecording::record_pose(double stamp, const Eigen::Isometry3d& map_from_base,
                               const Eigen::Isometry3d& map_from_odom) {
  if (empty())
    return;
  ros2::PoseWithCovarianceStamped pose;
  pose.header = header(stamp, replay::kMapFrame);
  pose.pose.pose = map_from_base;
  record({"/pose", ros2::PoseWithCovarianceStamped::kType, stamp, ros2::encode(pose)});
  ros2::TFMessage tf;
  tf.transforms.push_back({header(stamp, replay::kMapFrame), std::string(replay::kOdomFrame), map_from_odom});
  record({std::string(replay::kTfTopic), ros2::TFMessage::kType, stamp, ros2::encode(tf)});
}

void RunRecording::record_goal(const GoalStatus& goal, const PlannedPath* path, double stamp) {
  if (empty())
    return;
  bool goal_changed = false, path_changed = false;
  {
    std::lock_guard lock(mutex_);
    if (goal.id != 0 && (goal.id != goal_id_ || goal.phase != goal_phase_)) {
      goal_changed = true;
      goal_id_ = goal.id;
      goal_phase_ = goal.phase;
    }
    if (path != nullptr && (path->goal_id != path_goal_ || path->version != path_version_)) {
      path_changed = true;
      path_goal_ = path->goal_id;
      path_version_ = path->version;
    }
  }
  if (goal_changed) {
    nlohmann::json event{{"id", goal.id},         {"phase", to_string(goal.phase)},
                         {"reason", goal.reason}, {"message", goal.message},
                         {"stamp", goal.stamp},   {"target", {{"x", goal.target.x}, {"y", goal.target.y}}}};
    if (goal.target.z)
      event["target"]["z"] = *goal.target.z;
    record({"/goal_events", ros2::String::kType, stamp, ros2::encode(ros2::String{event.dump()})});
  }
  if (path_changed) {
    ros2::Path message;
    message.header = header(stamp, replay::kMapFrame);
    for (const Eigen::Vector3d& point : path->points) {
      ros2::PoseStamped pose{message.header, Eigen::Isometry3d::Identity()};
      pose.pose.translation() = point;
      message.poses.push_back(std::move(pose));
    }
    record({"/plan", ros2::Path::kType, stamp, ros2::encode(message)});
  }
}

void RunRecording::record_map(const MapUpdate& update) {
  if (empty() || !update.whole_level)
    return;
  double stamp = 0.0;
  {
    std::lock_guard lock(mutex_);
    stamp = latest_stamp_;
    if (map_recorded_at_ && stamp - *map_recorded_at_ < kMapPeriod) {
      held_map_ = update.whole_level;
      return;
    }
    map_recorded_at_ = stamp;
    held_map_ = nullptr;
  }
  record_grid(update.whole_level(), stamp);
}

void RunRecording::record_grid(const std::shared_ptr<const DrivableMap>& drivable, double stamp) {
  if (drivable == nullptr || drivable->grid.cells.empty())
    return;
  const ros2::OccupancyGrid grid = ros2::occupancy_grid(drivable->grid, header(stamp, replay::kMapFrame));
  record({std::string(replay::kMapTopic), ros2::OccupancyGrid::kType, stamp, ros2::encode(grid)});
}

void RunRecording::stop() {
  std::function<std::shared_ptr<const DrivableMap>()> held;
  double stamp = 0.0;
  {
    std::lock_guard lock(mutex_);
    held = std::exchange(held_map_, nullptr);
    stamp = latest_stamp_;
  }
  if (held)
    record_grid(held(), stamp);  // the mapping thread has stopped: the newest map, made here
  recorders_.clear();            // each writes what is queued and finishes its recording
}

}  // namespace strata::pipeline

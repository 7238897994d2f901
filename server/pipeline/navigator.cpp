#include "server/pipeline/navigator.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/navigation/patch_graph_planner.hpp"

namespace strata::pipeline {
namespace {

/// Metres the robot must move to count as making progress towards its goal.
constexpr double kProgress = 0.25;

/// Why a goal failed, for programs and in words (goal_state.hpp): one wording for the log, REST, the
/// WebSocket and the web UI.
struct Failure {
  std::string reason;
  std::string message;
};

Failure failure_for(PatchPlanStatus status, bool replanning) {
  switch (status) {
    case PatchPlanStatus::start_off_map:
      return {"robot_off_map", std::string(describe(status))};
    case PatchPlanStatus::goal_off_map:
      return {"off_map", std::string(describe(status))};
    case PatchPlanStatus::goal_blocked:
      return {"goal_not_drivable", std::string(describe(status))};
    case PatchPlanStatus::no_path:
    case PatchPlanStatus::found:
      break;
  }
  if (replanning)  // there was a way, and a new scan closed it
    return {"blocked", "the way to the goal is blocked: no drivable connection is left"};
  return {"no_connection", std::string(describe(status))};
}

/// How far around a goal that is no place for the robot the nearest one is looked for, metres.
constexpr double kNearestSearchRadius = 3.0;
/// How far a goal on ground too near an edge moves to a place with room, metres (as Nav2's default goal
/// tolerance): the goal drive bench's refusals on the yard were places 0.3-0.4 m from one.
constexpr double kRoomSearchRadius = 0.5;
/// A far goal may move further, this share of its distance up to kFarRoomSearchRadius: the live map knows
/// far ground only between a scanner's rings, so where its edges stand is that coarse (the campus lidar's
/// refusals were spots 8-19 m away, 0.6-1.4 m from a place with room). Fixed when the goal is accepted, so
/// a replan from near takes the spot asked for once it is seen to have room, and never refuses a goal it
/// accepted because the robot came closer.
constexpr double kRoomSearchShareOfDistance = 0.1;
constexpr double kFarRoomSearchRadius = 2.0;

double room_search_radius(const Eigen::Vector3d& robot, const GoalRequest& goal) {
  const double distance = std::hypot(goal.x - robot.x(), goal.y - robot.y());
  return std::clamp(kRoomSearchShareOfDistance * distance, kRoomSearchRadius, kFarRoomSearchRadius);
}

}  // namespace

Navigator::Navigator(NavigatorConfig config, Clock clock)
    : config_(std::move(config)), clock_(std::move(clock)), pursuit_(config_.pursuit) {}

Navigator::~Navigator() {
  stop();
}

void Navigator::start() {
  std::lock_guard lock(mutex_);
  if (thread_.joinable())
    return;
  stopping_ = false;
  thread_ = std::thread([this] {
    for (;;) {
      {
        std::unique_lock waiting(mutex_);
        wake_.wait(waiting, [this] { return stopping_ || planning_wanted(); });
        if (stopping_)
          return;
      }
      plan_pending();
    }
  });
}

void Navigator::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable())
    thread_.join();
}

CommandResult Navigator::set_goal(const GoalRequest& goal) {
  if (!std::isfinite(goal.x) || !std::isfinite(goal.y) || (goal.z && !std::isfinite(*goal.z)))
    return CommandResult::failure(ErrorCode::kBadParams, "goal coordinates must be finite numbers");
  CommandResult result = CommandResult::success();
  {
    std::lock_guard lock(mutex_);
    commanded_ = true;
    teleop_until_.reset();
    result.goal_id = tracker_.accept(goal, stamp_);
    drop_path();
    goal_waiting_ = true;
  }
  wake_.notify_all();
  return result;
}

CommandResult Navigator::cancel_goal() {
  std::lock_guard lock(mutex_);
  commanded_ = true;
  teleop_until_.reset();
  tracker_.cancel(stamp_);
  drop_path();
  goal_waiting_ = false;
  return CommandResult::success();
}

bool Navigator::cancel_goal_if_active(std::uint64_t goal_id, const std::string& reason) {
  std::lock_guard lock(mutex_);
  if (!tracker_.is_active(goal_id))
    return false;
  tracker_.cancel(
      stamp_, reason,
      reason == "operator_disconnected" ? "the operator connection that set the goal closed" : reason);
  drop_path();
  goal_waiting_ = false;
  return true;  // drive() now answers a stop: commanded_ was set with the goal
}

CommandResult Navigator::teleop(double v, double w, std::chrono::steady_clock::time_point sent) {
  if (!std::isfinite(v) || !std::isfinite(w))
    return CommandResult::failure(ErrorCode::kBadParams, "teleop v and w must be finite numbers");
  std::lock_guard lock(mutex_);
  commanded_ = true;
  tracker_.cancel(stamp_);  // the operator drives now
  drop_path();
  goal_waiting_ = false;
  teleop_ = {.v = std::clamp(v, -config_.max_speed, config_.max_speed),
             .w = std::clamp(w, -config_.max_turn_rate, config_.max_turn_rate),
             .by_hand = true};
  // The lease runs from when the operator sent it: a command that waited in the network drives less long.
  teleop_until_ = std::min(sent, clock_()) + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                 std::chrono::duration<double>(config_.teleop_timeout));
  return CommandResult::success();
}

void Navigator::stop_teleop() {
  std::lock_guard lock(mutex_);
  teleop_until_.reset();
}

GoalStatus Navigator::goal_status() const {
  std::lock_guard lock(mutex_);
  return tracker_.status();
}

std::shared_ptr<const PlannedPath> Navigator::path() const {
  std::lock_guard lock(mutex_);
  return path_;
}

void Navigator::on_map_update(const MapUpdate& update) {
  // The only work on the mapping thread: flatten and classify the map's patches (a copy the planner owns).
  const CellRegion region = CellRegion::of_tiles(update.map.tile_indices());
  auto surfaces = std::make_shared<const SurfaceGrid>(update.map, region, config_.graph.traversability);
  {
    std::lock_guard lock(mutex_);
    surfaces_ = std::move(surfaces);
    resolution_ = update.map.resolution();
    ++map_version_;
    map_changed_ = true;
  }
  wake_.notify_all();
}

void Navigator::map_rebuilding(bool rebuilding) {
  {
    std::lock_guard lock(mutex_);
    rebuilding_ = rebuilding;
    if (rebuilding)
      return;
    ++rebuilds_;
    if (!std::exchange(held_for_rebuild_, false) || tracker_.status().phase != GoalPhase::kPlanning)
      return;
    goal_waiting_ = true;  // judged again, on the rebuilt map
  }
  wake_.notify_all();
}

std::optional<DriveCommand> Navigator::drive(const Pose3& estimate, double stamp) {
  std::lock_guard lock(mutex_);
  pose_ = estimate;
  stamp_ = stamp;
  if (teleop_until_) {
    if (clock_() < *teleop_until_)
      return teleop_;
    teleop_until_.reset();  // expired: the operator stopped renewing it
  }
  // Not while a map that may open the way is still to come: a rebuild under way, or a map not yet judged
  // (at 5x a rebuild after a loop closure took longer than the grace, and a goal the rebuilt map opened
  // failed as blocked; issue 58).
  if (blocked_ && tracker_.status().phase == GoalPhase::kDriving && !rebuilding_ && !map_changed_ &&
      stamp - blocked_->since > config_.blocked_grace) {
    spdlog::info("goal {} failed ({}): {}", tracker_.status().id, blocked_->reason, blocked_->message);
    tracker_.fail(tracker_.status().id, blocked_->reason, blocked_->message, stamp, blocked_->nearest);
    drop_path();
  }
  if (tracker_.status().phase == GoalPhase::kDriving && pursuit_.has_path()) {
    if ((estimate.position - progress_position_).norm() > kProgress) {
      progress_position_ = estimate.position;
      progress_stamp_ = stamp;
    } else if (stamp - progress_stamp_ > config_.stuck_after) {
      const std::string message =
          fmt::format("the robot made no progress toward the goal for {:.0f} s", config_.stuck_after);
      spdlog::info("goal {} failed (stuck): {}", tracker_.status().id, message);
      tracker_.fail(tracker_.status().id, "stuck", message, stamp);
      drop_path();
      return DriveCommand{};
    }
    const PurePursuit::Output output = pursuit_.update(estimate);
    if (!output.arrived)
      return output.command;
    tracker_.reached(tracker_.status().id, stamp);
    drop_path();
  }
  if (!commanded_)
    return std::nullopt;
  return DriveCommand{};
}

bool Navigator::planning_wanted() const {
  return goal_waiting_ || (map_changed_ && tracker_.status().phase == GoalPhase::kDriving);
}

void Navigator::drop_path() {
  pursuit_.clear();
  path_.reset();
  blocked_.reset();
}

bool Navigator::plan_pending() {
  std::lock_guard planning(planning_mutex_);
  std::uint64_t id = 0;
  GoalRequest goal;
  Pose3 pose;
  bool replanning = false;
  std::shared_ptr<const SurfaceGrid> surfaces;
  double resolution = 0.1;
  std::uint64_t map_version = 0;
  std::uint64_t rebuilds = 0;
  {
    std::lock_guard lock(mutex_);
    if (!planning_wanted())
      return false;
    replanning = !goal_waiting_;
    goal_waiting_ = false;
    held_for_rebuild_ = false;
    map_changed_ = false;
    id = tracker_.status().id;
    goal = tracker_.status().target;
    if (!replanning)
      tracker_.planning(id, stamp_);
    pose = pose_;
    surfaces = surfaces_;
    resolution = resolution_;
    map_version = map_version_;
    rebuilds = rebuilds_;
    if (!surfaces) {
      spdlog::info("goal {}: there is no map yet", id);
      tracker_.fail(id, "no_map", "there is no map yet", stamp_);
      return true;
    }
  }
  if (!graph_ || graph_version_ != map_version) {
    graph_ = std::make_shared<const PatchGraph>(surfaces, resolution, config_.graph);
    graph_version_ = map_version;
  }
  if (!replanning)
    room_search_radius_ = room_search_radius(pose.position, goal);
  const PatchGoal target{.x = goal.x,
                         .y = goal.y,
                         .z = goal.z,
                         .level_tolerance = 0.5,
                         .room_search_radius = room_search_radius_};
  const PatchPath planned = plan_on_patches(*graph_, pose.position, target);
  Failure failure;
  std::optional<Eigen::Vector3d> nearest;
  if (!planned.found()) {
    failure = failure_for(planned.status, replanning);
    if (planned.status == PatchPlanStatus::goal_blocked) {
      nearest = nearest_reachable(*graph_, pose.position, target, kNearestSearchRadius);
      if (nearest) {
        failure.message +=
            fmt::format("; the nearest place the robot can reach is ({:.2f}, {:.2f}, {:.2f}), {:.1f} m away",
                        nearest->x(), nearest->y(), nearest->z(),
                        std::hypot(nearest->x() - goal.x, nearest->y() - goal.y));
      }
    }
  }

  std::lock_guard lock(mutex_);
  if (!tracker_.is_active(id))
    return true;  // cancelled or replaced while planning
  if (!planned.found() && replanning) {
    // The way was open when the goal was accepted: stand still and give the map time to open it again.
    const double since = blocked_ ? blocked_->since : stamp_;
    if (!blocked_)
      spdlog::info("goal {}: {}; stopped, waiting up to {:.0f} s for the map to open a way", id,
                   failure.message, config_.blocked_grace);
    drop_path();
    blocked_ =
        Blocked{.since = since, .reason = failure.reason, .message = failure.message, .nearest = nearest};
    tracker_.driving(id, stamp_,
                     fmt::format("{}: stopped, waiting for a scan that opens a way", failure.message));
    return true;
  }
  if (!planned.found() && (rebuilding_ || rebuilds_ != rebuilds)) {
    // Judged on a map a loop closure has made stale: the rebuilt one judges it (map_rebuilding).
    if (rebuilding_) {
      spdlog::info("goal {}: {} on the map before the loop closure; waiting for the map rebuilt after it", id,
                   failure.message);
      held_for_rebuild_ = true;
    } else {
      goal_waiting_ = true;
      wake_.notify_all();
    }
    return true;
  }
  if (!planned.found()) {
    spdlog::info("goal {} failed ({}): {}", id, failure.reason, failure.message);
    tracker_.fail(id, failure.reason, failure.message, stamp_, nearest);
    drop_path();
    return true;
  }
  const bool reopened = blocked_.has_value();
  if (reopened)
    spdlog::info("goal {}: the way is open again", id);
  blocked_.reset();
  auto path = std::make_shared<PlannedPath>();
  path->goal_id = id;
  path->version = ++path_version_;
  path->points = planned.points;
  path->length = planned.length;
  path_ = std::move(path);
  pursuit_.set_path(planned.points);
  if (!replanning || reopened) {  // standing while blocked is no lack of progress
    progress_position_ = pose_.position;
    progress_stamp_ = stamp_;
  }
  std::string moved = reopened ? "the way is open again" : "";
  if (planned.moved_goal) {
    moved = fmt::format(
        "the spot asked for is too near an edge for the robot: driving to the nearest place "
        "with room, ({:.2f}, {:.2f}, {:.2f}), {:.1f} m away",
        planned.moved_goal->x(), planned.moved_goal->y(), planned.moved_goal->z(),
        std::hypot(planned.moved_goal->x() - goal.x, planned.moved_goal->y() - goal.y));
    if (!replanning)
      spdlog::info("goal {}: {}", id, moved);
  }
  tracker_.driving(id, stamp_, std::move(moved));
  return true;
}

}  // namespace strata::pipeline

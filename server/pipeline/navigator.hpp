#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "core/geometry/pose.hpp"
#include "core/navigation/drive_command.hpp"
#include "core/navigation/patch_graph.hpp"
#include "core/navigation/pure_pursuit.hpp"
#include "server/control/robot_commands.hpp"
#include "server/pipeline/map_update.hpp"
#include "server/state/goal_tracker.hpp"

namespace strata::pipeline {

struct NavigatorConfig {
  PatchGraphConfig graph{.clearance_weight = 2.0};
  PurePursuitConfig pursuit;
  double teleop_timeout = 0.5;  ///< seconds (steady clock) a teleop command lasts unless renewed
  double max_speed = 1.0;       ///< m/s, teleop is clamped to it
  double max_turn_rate = 1.2;   ///< rad/s, teleop is clamped to it
  /// A goal fails as "stuck" when the robot, driving to it, has not moved 0.25 m in this many robot seconds
  /// (a bumper stop the map does not explain). Longer than a stop-and-go scan plus a turn on the spot.
  double stuck_after = 20.0;
  /// A replan that finds the way closed (a new scan blocks it, or a loop closure moved the pose before the
  /// rebuilt map arrived) stops the robot and waits this many robot seconds for a map that opens it again
  /// before the goal fails: a rebuild after a loop closure takes seconds, a person in a doorway longer. A
  /// rebuild under way, or a map not yet planned on, extends the wait until it is judged.
  double blocked_grace = 20.0;
};

/// Drives the robot to operators' goals (docs/architecture.md 4.4): plans across levels on the patch graph of
/// the latest map, follows the path with pure pursuit on the localized pose, replans on every new map (a
/// path a new scan blocks is left, a shorter one that a scan reveals is taken; when none is left the robot
/// stops and waits NavigatorConfig::blocked_grace for a map that opens one), and passes teleoperation
/// through. Thread-safe: operators call MotionCommands from the network threads, the mapping worker calls
/// on_map_update, the driver thread calls drive(), and planning runs on the navigator's own thread
/// (start()) or, in tests, wherever plan_pending() is called.
class Navigator : public MotionCommands {
 public:
  using Clock = std::function<std::chrono::steady_clock::time_point()>;

  explicit Navigator(
      NavigatorConfig config = {}, Clock clock = [] { return std::chrono::steady_clock::now(); });
  ~Navigator() override;
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// The planning thread; stop() joins it.
  void start();
  void stop();

  // MotionCommands
  CommandResult set_goal(const GoalRequest& goal) override;
  CommandResult cancel_goal() override;
  bool cancel_goal_if_active(std::uint64_t goal_id, const std::string& reason) override;
  CommandResult teleop(double v, double w, std::chrono::steady_clock::time_point sent) override;
  /// Sent now (tests, and commands that carry no stamp).
  CommandResult teleop(double v, double w) { return teleop(v, w, clock_()); }
  void stop_teleop() override;
  [[nodiscard]] GoalStatus goal_status() const override;
  [[nodiscard]] std::shared_ptr<const PlannedPath> path() const override;

  /// The MapUpdate listener (mapping thread): keeps the drivable surfaces of the whole map for planning.
  void on_map_update(const MapUpdate& update);
  [[nodiscard]] MapUpdateListener map_listener() {
    return [this](const MapUpdate& update) { on_map_update(update); };
  }

  /// A loop closure moved the keyframes and the map is being rebuilt from them (true), or the rebuild is
  /// over (false; its map, if any, came through on_map_update first). Meanwhile the map holds the drift
  /// the loop corrected: a new goal it refuses waits for the rebuilt map and is judged on that. On the
  /// lidar demo the first goal down the bridge ramp after a loop closure was refused ("no drivable
  /// connection") on the old map 3 s before the rebuilt one, which planned it, arrived (issue 58).
  void map_rebuilding(bool rebuilding);

  /// The driver thread, every step: the command for the robot at `estimate` (map frame, z the ground it
  /// stands on) at robot time `stamp`. Nothing until an operator has sent a goal or teleop, so the
  /// simulator keeps driving its demo route until then; afterwards a stop when there is nothing to do.
  [[nodiscard]] std::optional<DriveCommand> drive(const Pose3& estimate, double stamp);

  /// Plans if a new goal waits or a new map arrived while driving; returns whether it planned.
  bool plan_pending();

 private:
  [[nodiscard]] bool planning_wanted() const;  // with mutex_ held
  void drop_path();                            // with mutex_ held

  NavigatorConfig config_;
  Clock clock_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  GoalTracker tracker_;
  PurePursuit pursuit_;
  std::shared_ptr<const PlannedPath> path_;
  std::uint64_t path_version_ = 0;
  std::shared_ptr<const SurfaceGrid> surfaces_;
  double resolution_ = 0.1;
  std::uint64_t map_version_ = 0;
  bool goal_waiting_ = false;      // a goal was accepted and not planned yet
  bool map_changed_ = false;       // a map arrived since the last plan
  bool rebuilding_ = false;        // a rebuild after a loop closure is under way (map_rebuilding)
  std::uint64_t rebuilds_ = 0;     // rebuilds over: a plan that read the map before one is stale
  bool held_for_rebuild_ = false;  // a new goal the old map refused waits for the rebuild
  Pose3 pose_;
  double stamp_ = 0.0;
  bool commanded_ = false;  // an operator has taken over from the demo route
  Eigen::Vector3d progress_position_ = Eigen::Vector3d::Zero();  // where the robot last made progress
  double progress_stamp_ = 0.0;                                  // and when
  /// Set while the robot stands because a replan found no way: since when, and why the goal fails if no
  /// map opens the way within blocked_grace.
  struct Blocked {
    double since = 0.0;
    std::string reason;
    std::string message;
    std::optional<Eigen::Vector3d> nearest;
  };
  std::optional<Blocked> blocked_;
  DriveCommand teleop_;
  std::optional<std::chrono::steady_clock::time_point> teleop_until_;
  bool stopping_ = false;

  std::mutex planning_mutex_;  // one plan at a time; guards the graph cache
  std::shared_ptr<const PatchGraph> graph_;
  std::uint64_t graph_version_ = 0;
  double room_search_radius_ = 0.0;  // how far the goal may move to a place with room, set on acceptance
  std::thread thread_;
};

}  // namespace strata::pipeline

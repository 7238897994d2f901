#pragma once

#include <cstdint>
#include <string>

#include "server/state/goal_state.hpp"

namespace strata {

/// One goal's life (docs/architecture.md 4.4): accepted -> planning -> driving -> reached | failed(reason) |
/// cancelled, with one active goal at a time: a new goal replaces the old one. Transitions that do not
/// follow the arrows are refused (return false) and change nothing, so a late planner result cannot
/// revive a goal that was cancelled or replaced meanwhile. Not thread-safe: its owner locks.
class GoalTracker {
 public:
  /// Accepts a new goal, replacing any active one; returns its id.
  std::uint64_t accept(const GoalRequest& request, double stamp);
  bool planning(std::uint64_t id, double stamp);
  /// `message`, when not empty, says what the driving goal is in words (where it was moved to).
  bool driving(std::uint64_t id, double stamp, std::string message = {});
  bool reached(std::uint64_t id, double stamp);
  bool fail(std::uint64_t id, std::string reason, std::string message, double stamp,
            std::optional<Eigen::Vector3d> nearest_reachable = std::nullopt);
  /// Cancels the active goal, if there is one; `reason` says why when no command did (empty: one did),
  /// `message` the same in words.
  bool cancel(double stamp, std::string reason = {}, std::string message = {});

  [[nodiscard]] const GoalStatus& status() const { return status_; }
  /// accepted, planning or driving.
  [[nodiscard]] bool active() const;
  [[nodiscard]] bool is_active(std::uint64_t id) const { return active() && status_.id == id; }

 private:
  bool move(std::uint64_t id, GoalPhase from_at_least, GoalPhase to, double stamp);

  GoalStatus status_;
  std::uint64_t next_id_ = 1;
};

}  // namespace strata

#include "server/state/goal_tracker.hpp"

#include <utility>

namespace strata {

std::uint64_t GoalTracker::accept(const GoalRequest& request, double stamp) {
  status_ = GoalStatus{.id = next_id_++, .target = request, .phase = GoalPhase::kAccepted, .stamp = stamp};
  return status_.id;
}

bool GoalTracker::active() const {
  return status_.id != 0 && (status_.phase == GoalPhase::kAccepted || status_.phase == GoalPhase::kPlanning ||
                             status_.phase == GoalPhase::kDriving);
}

bool GoalTracker::move(std::uint64_t id, GoalPhase from_at_least, GoalPhase to, double stamp) {
  if (!is_active(id) || static_cast<int>(status_.phase) < static_cast<int>(from_at_least))
    return false;
  status_.phase = to;
  status_.stamp = stamp;
  return true;
}

// Planning may be entered again from driving (a replan); driving again from planning.
bool GoalTracker::planning(std::uint64_t id, double stamp) {
  return move(id, GoalPhase::kAccepted, GoalPhase::kPlanning, stamp);
}

bool GoalTracker::driving(std::uint64_t id, double stamp, std::string message) {
  if (!move(id, GoalPhase::kPlanning, GoalPhase::kDriving, stamp))
    return false;
  if (!message.empty())
    status_.message = std::move(message);
  return true;
}

bool GoalTracker::reached(std::uint64_t id, double stamp) {
  return move(id, GoalPhase::kDriving, GoalPhase::kReached, stamp);
}

bool GoalTracker::fail(std::uint64_t id, std::string reason, std::string message, double stamp,
                       std::optional<Eigen::Vector3d> nearest_reachable) {
  if (!move(id, GoalPhase::kAccepted, GoalPhase::kFailed, stamp))
    return false;
  status_.reason = std::move(reason);
  status_.message = std::move(message);
  status_.nearest_reachable = nearest_reachable;
  return true;
}

bool GoalTracker::cancel(double stamp, std::string reason, std::string message) {
  if (!active())
    return false;
  status_.phase = GoalPhase::kCancelled;
  status_.stamp = stamp;
  status_.reason = std::move(reason);
  status_.message = std::move(message);
  return true;
}

}  // namespace strata

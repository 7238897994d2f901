#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "server/control/robot_commands.hpp"
#include "server/streams/outgoing_message.hpp"

namespace strata::streams {

/// The goal and path streams: polls the navigator and sends `goal` when the goal or its phase changes and
/// `path` when a new path is planned (or the path is cleared).
class NavigationStream {
 public:
  explicit NavigationStream(const MotionCommands& motion) : motion_(motion) {}

  [[nodiscard]] std::vector<streams::OutgoingMessage> poll();
  /// The current goal and path, for a late joiner. Thread-safe.
  [[nodiscard]] std::vector<streams::OutgoingMessage> current() const;

 private:
  const MotionCommands& motion_;
  mutable std::mutex mutex_;
  double sequence_ = 0.0;
  std::optional<GoalStatus> goal_;
  std::optional<streams::OutgoingMessage> goal_message_;
  std::shared_ptr<const PlannedPath> path_;
  bool path_sent_ = false;
  std::optional<streams::OutgoingMessage> path_message_;
};

}  // namespace strata::streams

#include "server/streams/navigation_stream.hpp"

#include "server/protocol/client_messages.hpp"
#include "server/protocol/messages.hpp"

namespace strata::streams {
namespace {

bool same_goal(const GoalStatus& a, const GoalStatus& b) {
  return a.id == b.id && a.phase == b.phase && a.reason == b.reason;
}

}  // namespace

std::vector<streams::OutgoingMessage> NavigationStream::poll() {
  const GoalStatus goal = motion_.goal_status();
  const auto path = motion_.path();
  std::lock_guard lock(mutex_);
  std::vector<streams::OutgoingMessage> changed;
  if (!goal_ || !same_goal(*goal_, goal)) {
    goal_ = goal;
    goal_message_ = streams::OutgoingMessage::text(protocol::goal_message(goal), "goal", ++sequence_,
                                                   static_cast<std::uint8_t>(protocol::Stream::kGoal));
    changed.push_back(*goal_message_);
  }
  if (!path_sent_ || path != path_) {
    path_ = path;
    path_sent_ = true;
    path_message_ = streams::OutgoingMessage::text(protocol::path_message(path.get()), "path", ++sequence_,
                                                   static_cast<std::uint8_t>(protocol::Stream::kPath));
    changed.push_back(*path_message_);
  }
  return changed;
}

std::vector<streams::OutgoingMessage> NavigationStream::current() const {
  std::lock_guard lock(mutex_);
  std::vector<streams::OutgoingMessage> messages;
  if (goal_message_)
    messages.push_back(*goal_message_);
  if (path_message_)
    messages.push_back(*path_message_);
  return messages;
}

}  // namespace strata::streams

#include "server/net/send_queue.hpp"

#include <utility>

namespace strata::net {

SendQueue::PushResult SendQueue::push(streams::OutgoingMessage message) {
  if (message.coalesce_key.empty()) {
    if (plain_ >= capacity_)
      return PushResult::kOverflow;
    ++plain_;
    ++unsent_;
    bytes_ += size_of(message);
    lane_of(message).emplace_back(std::move(message));
    return PushResult::kQueued;
  }
  // A stream only moves forward: drop what is not newer than the last message queued for the key.
  auto [key, inserted] = keys_.try_emplace(message.coalesce_key);
  KeyState& state = key->second;
  if (!inserted && message.order && state.order && *message.order <= *state.order)
    return PushResult::kStale;
  state.order = message.order;
  bytes_ += size_of(message);
  if (state.unsent) {
    bytes_ -= size_of(*state.unsent);
    ++superseded_;
    state.unsent = std::move(message);
    return PushResult::kCoalesced;
  }
  lane_of(message).emplace_back(message.coalesce_key);
  state.unsent = std::move(message);
  ++unsent_;
  return PushResult::kQueued;
}

const streams::OutgoingMessage* SendQueue::start_write() {
  if (writing())
    return nullptr;
  for (auto& lane : lanes_) {
    if (lane.empty())
      continue;
    Entry next = std::move(lane.front());
    lane.pop_front();
    --unsent_;
    if (auto* plain = std::get_if<streams::OutgoingMessage>(&next)) {
      in_flight_ = std::move(*plain);
    } else {
      auto& unsent = keys_.at(std::get<std::string>(next)).unsent;
      in_flight_ = std::move(*unsent);
      unsent.reset();
    }
    return &*in_flight_;
  }
  return nullptr;
}

void SendQueue::finish_write() {
  if (!in_flight_)
    return;
  if (in_flight_->coalesce_key.empty())
    --plain_;
  bytes_ -= size_of(*in_flight_);
  in_flight_.reset();
}

}  // namespace strata::net

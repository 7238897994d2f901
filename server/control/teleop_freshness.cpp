#include "server/control/teleop_freshness.hpp"

#include <spdlog/fmt/fmt.h>

namespace strata {

CommandResult TeleopFreshness::admit(const std::optional<TeleopStamp>& stamp, bool moves, double now_ms) {
  if (!stamp) {
    if (!moves)
      return CommandResult::success();
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "a teleop that moves the robot needs \"seq\" and \"t\" (the server's clock_ms "
        "from hello or pong, in ms): stale commands must be told apart");
  }
  if (last_seq_ && stamp->seq <= *last_seq_) {
    if (!moves)
      return CommandResult::success();
    return CommandResult::failure(
        ErrorCode::kStaleCommand,
        fmt::format("teleop seq {} is not newer than {}: out of order, not obeyed", stamp->seq, *last_seq_));
  }
  const double age_ms = now_ms - stamp->sent_ms;
  if (moves && age_ms > kMaxAgeMs) {
    return CommandResult::failure(
        ErrorCode::kStaleCommand,
        fmt::format("teleop sent {:.0f} ms ago (at most {:.0f}): stale, not obeyed", age_ms, kMaxAgeMs));
  }
  if (moves && -age_ms > kMaxLeadMs) {
    return CommandResult::failure(
        ErrorCode::kStaleCommand,
        fmt::format("teleop \"t\" is {:.0f} ms ahead of the server clock: take clock_ms from hello or pong",
                    -age_ms));
  }
  last_seq_ = stamp->seq;
  return CommandResult::success();
}

}  // namespace strata

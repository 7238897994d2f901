#pragma once

#include <cstdint>
#include <optional>

#include "server/control/robot_commands.hpp"

namespace strata {

/// When an operator sent a teleop command: its place in the connection's sequence and the server clock
/// (server_clock.hpp) as the client read it at sending.
struct TeleopStamp {
  std::uint64_t seq = 0;
  double sent_ms = 0.0;
};

/// Decides, per connection, whether a teleop command still says what the operator wants now. Commands that
/// waited out a link outage arrive together when it returns; obeyed, each would renew the lease and drive
/// the robot on intent seconds old. So a command that moves the robot must be stamped, recent, and newer
/// than every command accepted before it; a command that stops it is always obeyed (stopping is safe
/// whatever its age). docs/architecture.md 6, proto/PROTOCOL.md "Teleoperation".
class TeleopFreshness {
 public:
  /// Older than this (by the server's clock) a moving command is refused: a Wi-Fi link's delay and jitter
  /// stay well below, a burst after an outage is far above.
  static constexpr double kMaxAgeMs = 250.0;
  /// Further ahead of the server's clock than this, the client's clock estimate is wrong: refused too.
  static constexpr double kMaxLeadMs = 250.0;

  /// Success, or kStaleCommand / kBadParams saying why the command must not move the robot. Remembers an
  /// accepted command's sequence number.
  CommandResult admit(const std::optional<TeleopStamp>& stamp, bool moves, double now_ms);

 private:
  std::optional<std::uint64_t> last_seq_;
};

}  // namespace strata

#pragma once

#include <chrono>

namespace strata {

/// The server's clock on the wire: milliseconds of the steady clock (on Linux, since boot). `hello` and
/// `pong` carry it so that a client can stamp commands in it (proto/PROTOCOL.md, "Teleoperation").
[[nodiscard]] inline double server_clock_ms(std::chrono::steady_clock::time_point time) {
  return std::chrono::duration<double, std::milli>(time.time_since_epoch()).count();
}
[[nodiscard]] inline double server_clock_ms() {
  return server_clock_ms(std::chrono::steady_clock::now());
}
[[nodiscard]] inline std::chrono::steady_clock::time_point from_server_clock_ms(double ms) {
  return std::chrono::steady_clock::time_point(
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double, std::milli>(ms)));
}

}  // namespace strata

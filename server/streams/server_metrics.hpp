#pragma once

#include <atomic>
#include <cstdint>

namespace strata::streams {

/// Counters for GET /metrics (Prometheus text format). Relaxed atomics: counts, not synchronisation.
struct ServerMetrics {
  std::atomic<std::uint64_t> http_requests{0};
  std::atomic<std::uint64_t> ws_connections{0};     ///< accepted since start
  std::atomic<std::uint64_t> ws_messages_in{0};     ///< client messages received
  std::atomic<std::uint64_t> ws_errors_sent{0};     ///< client messages refused
  std::atomic<std::uint64_t> ws_rate_limited{0};    ///< client messages refused for the rate limit
  std::atomic<std::uint64_t> ws_stale_teleop{0};    ///< moving teleops refused as stale or out of order
  std::atomic<std::uint64_t> ws_slow_dropped{0};    ///< clients disconnected: not reading, or silent
  std::atomic<std::uint64_t> ws_bytes_out{0};       ///< payload bytes written to WebSocket clients
  std::atomic<std::uint64_t> auth_failures{0};      ///< requests or upgrades with a wrong token
  std::atomic<std::uint64_t> ws_refused_origin{0};  ///< upgrades from a browser origin not allowed
  std::atomic<std::uint64_t> ws_refused_full{0};    ///< upgrades refused at the WebSocket client limit
  std::atomic<std::uint64_t> http_refused_full{0};  ///< connections refused at the HTTP connection limit
  std::atomic<std::uint64_t> refused_address{0};    ///< connections refused at the per-address limit
  std::atomic<std::uint64_t> refused_host{0};       ///< requests naming a Host that is not allowed
};

}  // namespace strata::streams

#pragma once

#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <utility>

#include "server/protocol/messages.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"
#include "server/streams/client_hub.hpp"

namespace strata::streams {

/// The status stream: registration quality, scan rate over the last 10 s, map size, clients and whether
/// the sensor's scans arrive.
class StatusStream {
 public:
  StatusStream(const RobotState& robot, const MapState* map, const streams::ClientHub& hub)
      : robot_(robot), map_(map), hub_(hub) {}

  /// The status now (also GET /api/v1/status). Thread-safe.
  [[nodiscard]] nlohmann::json fields() const;
  /// Records the scan count for the rate and returns the `status` message. Called at 1 Hz.
  [[nodiscard]] std::string poll();

 private:
  [[nodiscard]] protocol::StatusExtras extras() const;

  const RobotState& robot_;
  const MapState* map_;
  const streams::ClientHub& hub_;
  mutable std::mutex mutex_;
  std::deque<std::pair<std::chrono::steady_clock::time_point, std::size_t>> samples_;
  bool sensor_stalled_ = false;  // as last polled, for the log
};

}  // namespace strata::streams

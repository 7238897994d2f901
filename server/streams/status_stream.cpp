#include "server/streams/status_stream.hpp"

#include <spdlog/spdlog.h>

namespace strata::streams {
namespace {

constexpr auto kRateWindow = std::chrono::seconds(10);

}  // namespace

protocol::StatusExtras StatusStream::extras() const {
  protocol::StatusExtras extras;
  extras.clients = hub_.size();
  extras.map = map_ != nullptr ? map_->snapshot() : nullptr;
  extras.driver = robot_.driver();
  extras.sensor = robot_.sensor();
  std::lock_guard lock(mutex_);
  if (samples_.size() >= 2) {
    const double seconds =
        std::chrono::duration<double>(samples_.back().first - samples_.front().first).count();
    if (seconds > 0.0)
      extras.scan_rate = static_cast<double>(samples_.back().second - samples_.front().second) / seconds;
  }
  return extras;
}

nlohmann::json StatusStream::fields() const {
  return protocol::status_fields(robot_.registration(), extras());
}

std::string StatusStream::poll() {
  const auto registration = robot_.registration();
  {
    std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    samples_.emplace_back(now, registration.scans);
    while (samples_.size() > 2 && now - samples_.front().first > kRateWindow)
      samples_.pop_front();
  }
  const protocol::StatusExtras now = extras();
  // The log says when the sensor stalls and when it is back, once each (the status says it every second).
  if (now.sensor.stalled != sensor_stalled_) {
    sensor_stalled_ = now.sensor.stalled;
    if (sensor_stalled_) {
      spdlog::warn("sensor stalled: a scan has been due for {:.1f} s (timeout {:.1f} s)", now.sensor.overdue,
                   now.sensor.timeout);
    } else {
      spdlog::info("sensor recovered: scans are arriving again");
    }
  }
  return protocol::status_message(registration, now);
}

}  // namespace strata::streams

#pragma once

#include <mutex>
#include <optional>

#include "drivers/scan_event.hpp"
#include "drivers/sim/simulator.hpp"

namespace strata {

/// The latest robot sample, written by the driver thread and read by the network side. A plain
/// mutex-protected copy: the sample is small and readers want the newest, never a history.
class RobotState {
 public:
  void publish(const sim::RobotSample& sample) {
    std::lock_guard lock(mutex_);
    latest_ = sample;
  }
  [[nodiscard]] std::optional<sim::RobotSample> latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }

  /// Counts completed scans (the mapping pipeline consumes them in a later step).
  void publish_scan(const ScanEvent& /*scan*/) {
    std::lock_guard lock(mutex_);
    ++scans_;
  }
  [[nodiscard]] std::size_t scans() const {
    std::lock_guard lock(mutex_);
    return scans_;
  }

 private:
  mutable std::mutex mutex_;
  std::optional<sim::RobotSample> latest_;
  std::size_t scans_ = 0;
};

}  // namespace strata

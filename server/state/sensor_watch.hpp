#pragma once

#include <chrono>
#include <cstddef>
#include <optional>

namespace strata {

/// What the status reports about the 3D sensor: whether its scans arrive when they are due.
struct SensorStatus {
  bool stalled = false;                           ///< a due scan has been waited for longer than the timeout
  std::optional<double> seconds_since_last_scan;  ///< wall clock; none before the first scan
  double overdue = 0.0;                           ///< seconds a due scan has been waited for so far
  double timeout = 0.0;                           ///< seconds of waiting that count as stalled
  std::size_t scans = 0;                          ///< scans the driver has delivered
};

/// Notices a sensor that stops delivering scans (a loose cable, a crashed sensor driver, a lidar that stops
/// sending) and that it recovers (the next scan). It times only the stretches in which a scan is due
/// (RobotSample::awaiting_scan): always for a spinning lidar, a replay or a capture, and for the stop-and-go
/// scanner only while it scans, so a robot standing or driving between its scans is not a stalled sensor.
/// The wall clock, not robot time: a live lidar's driver sends samples only with its scans, so robot time
/// stops with the sensor. Not thread-safe: RobotState locks around it.
class SensorWatch {
 public:
  using Clock = std::chrono::steady_clock;

  explicit SensorWatch(double timeout_seconds = 10.0) : timeout_(timeout_seconds) {}

  void set_timeout(double seconds) { timeout_ = seconds; }

  /// The driver's thread, with every sample: whether a scan is due from now on.
  void sample(bool awaiting_scan, Clock::time_point now) {
    if (awaiting_ && !finished_)
      overdue_ += now - last_sample_;
    last_sample_ = now;
    awaiting_ = awaiting_scan;
  }

  /// The driver's thread, with every scan it delivers.
  void scan(Clock::time_point now) {
    ++scans_;
    last_scan_ = now;
    last_sample_ = now;
    overdue_ = Clock::duration::zero();
  }

  /// A finite source (a replay, a capture) has delivered everything: no scan is due any more.
  void finished() { finished_ = true; }

  [[nodiscard]] SensorStatus status(Clock::time_point now) const {
    SensorStatus status;
    status.timeout = timeout_;
    status.scans = scans_;
    if (scans_ > 0)
      status.seconds_since_last_scan = seconds(now - last_scan_);
    // Until the next sample comes, the current stretch counts as it was: a driver that stops sending
    // samples while a scan is due is as stalled as a silent sensor.
    Clock::duration overdue = overdue_;
    if (awaiting_ && !finished_ && now > last_sample_)
      overdue += now - last_sample_;
    status.overdue = seconds(overdue);
    status.stalled = status.overdue > timeout_;
    return status;
  }

 private:
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

  double timeout_;
  bool awaiting_ = false;  // until the first sample says otherwise
  bool finished_ = false;
  std::size_t scans_ = 0;
  Clock::time_point last_sample_{};
  Clock::time_point last_scan_{};
  Clock::duration overdue_{};
};

}  // namespace strata

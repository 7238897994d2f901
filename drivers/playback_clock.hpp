#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "drivers/robot_driver.hpp"

namespace strata {

/// How a recorded source (a dataset replay, a packet capture) is played.
struct PlaybackPacing {
  double time_scale = 1.0;           ///< recorded seconds per wall-clock second; ignored as fast as possible
  bool as_fast_as_possible = false;  ///< each scan once the pipeline has finished the one before
};

/// The one clock of every recorded source: when a recorded stamp is due on the wall clock, the pipeline's
/// back-pressure as fast as possible, and a stop that ends any wait at once. Used from the source's thread;
/// stop() from any thread.
class PlaybackClock {
 public:
  /// Throws std::invalid_argument for a time scale that is not positive (when it is used).
  explicit PlaybackClock(PlaybackPacing pacing) : pacing_(pacing) {
    if (!pacing_.as_fast_as_possible && !(pacing_.time_scale > 0.0))
      throw std::invalid_argument("the playback's time scale must be positive");
  }

  /// Waits until recorded time `stamp` is due: the first stamp at once, each later one when its distance
  /// from the first, divided by the time scale, has passed since then; never as fast as possible. False
  /// when stopped.
  bool wait_until_due(double stamp) {
    if (!first_stamp_) {
      first_stamp_ = stamp;
      started_ = clock::now();
    }
    std::unique_lock lock(mutex_);
    if (!pacing_.as_fast_as_possible) {
      const auto due = started_ + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(
                                      (stamp - *first_stamp_) / pacing_.time_scale));
      wake_.wait_until(lock, due, [this] { return stopping_; });
    }
    return !stopping_;
  }

  /// After a scan was handed on. As fast as possible, waits until the pipeline has finished it: the
  /// localizer keeps only the newest waiting scan, so none is dropped. False when the pipeline or the
  /// clock stopped.
  bool wait_for_pipeline(const RobotDriver::PipelineIdle& pipeline_idle) const {
    if (pacing_.as_fast_as_possible && pipeline_idle && !pipeline_idle())
      return false;
    return !stopped();
  }

  /// Ends the wait under way and every later one.
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
  }
  [[nodiscard]] bool stopped() const {
    std::lock_guard lock(mutex_);
    return stopping_;
  }

  /// "as fast as possible" or "time scale 2", for a driver's description.
  [[nodiscard]] std::string description() const {
    if (pacing_.as_fast_as_possible)
      return "as fast as possible";
    std::string scale = std::to_string(pacing_.time_scale);
    scale.erase(scale.find_last_not_of('0') + 1);  // 2.000000 -> 2.
    if (!scale.empty() && scale.back() == '.')
      scale.pop_back();
    return "time scale " + scale;
  }
  /// Wall-clock seconds since the first stamp was due (0 before).
  [[nodiscard]] double seconds_playing() const {
    return first_stamp_ ? std::chrono::duration<double>(clock::now() - started_).count() : 0.0;
  }

 private:
  using clock = std::chrono::steady_clock;
  PlaybackPacing pacing_;
  std::optional<double> first_stamp_;
  clock::time_point started_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
};

}  // namespace strata

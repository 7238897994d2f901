#pragma once

#include <Eigen/Geometry>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "core/localization/localizer.hpp"
#include "drivers/scan_event.hpp"
#include "server/control/robot_commands.hpp"
#include "server/pipeline/imu_calibration_store.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "server/state/robot_state.hpp"

namespace strata::pipeline {

/// The localizer's mailbox and thread: takes scans from the driver thread without blocking it, runs each
/// through the core Localizer on its own thread, and publishes the corrected pose and the status. When
/// scans come faster than localization (a 10 Hz lidar), the newest waiting scan replaces an older one:
/// the pose stays current and the driver never waits (docs/architecture.md 3). Behind it, on a thread of
/// its own, the pose graph looks for loop closures and optimizes; its corrections reach the scan path at
/// the next scan, so registration never waits for it.
class LocalizerWorker final : public LocalizationCommands {
 public:
  /// What became of one scan on the scan path, for benchmarks (tests/bench/sequence_bench.cpp): where the
  /// base was put, what the driver knows of the truth, how the scan registered, and what it cost.
  struct ScanReport {
    double stamp = 0.0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the base in the map frame after the scan
    std::optional<Pose3> truth;                              ///< the driver's truth or reference, if any
    bool registered = false;                                 ///< a registration ran (not the first scan)
    Correction correction = Correction::kNone;
    double rmse = 0.0;  ///< the registration's, m
    LocalizationState state = LocalizationState::kDegraded;
    double cpu_ms = 0.0;  ///< the localizer thread's CPU time for the scan, preprocessing to hand-on
  };
  using ScanObserver = std::function<void(const ScanReport& outcome)>;

  LocalizerWorker(RobotState& state, GraphLocalizerOptions options,
                  const Eigen::Isometry3d& initial_map_from_odom);
  ~LocalizerWorker() override;
  LocalizerWorker(const LocalizerWorker&) = delete;
  LocalizerWorker& operator=(const LocalizerWorker&) = delete;

  /// Where each registered scan goes next (the mapping worker): the scan as the driver took it and its
  /// sensor's corrected pose in the map frame, on the localizer's thread. Scans whose registration fault
  /// control rejected are not handed on: their pose is the odometry guess, which would smear the map with
  /// the very error the check caught (the first scan, which has nothing to register against, is).
  /// The scan comes preprocessed (step 1, in the base frame): nothing after the localizer does it again.
  /// `anchor`: the keyframe it came after, which a map rebuild moves it with (none without a pose graph).
  using RegisteredScanSink =
      std::function<void(PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                         const std::optional<KeyframeAnchor>& anchor)>;
  /// Before start().
  void set_registered_scan_sink(RegisteredScanSink sink) { sink_ = std::move(sink); }
  /// Where the keyframes go after the pose graph moved them (the mapping worker, to rebuild the map from
  /// them): all keyframes at their new poses, on the pose graph's thread. Before start().
  using KeyframesMovedSink = std::function<void(const std::vector<KeyframePose>& keyframes)>;
  void set_keyframes_moved_sink(KeyframesMovedSink sink) { keyframes_sink_ = std::move(sink); }

  /// Starts from the IMU calibration `store` keeps, if any, and keeps the pose graph's estimate there
  /// after each loop closure. `store` outlives the worker. Before start().
  void keep_imu_calibration(ImuCalibrationStore& store);
  /// Called on the localizer's thread after every scan it processed (not those dropped). Before start().
  void set_scan_observer(ScanObserver observer) { observer_ = std::move(observer); }

  void start();
  void stop();
  /// Called from the driver thread; returns at once.
  void submit(ScanEvent scan);
  /// From now on, localizes in `map` (a loaded map's, map frame; GraphLocalizer::localize_in), or
  /// with null maps again. Any thread; returns at once.
  void localize_in(std::shared_ptr<const LocalizationMap> map);
  /// Any thread; the localizer's thread searches around it at once with the latest scan, carried back to
  /// where the robot took that scan by the odometry since (Relocalizer::around), or with the next scan
  /// when there is none yet.
  CommandResult set_pose_estimate(const PoseEstimate& estimate) override;
  /// The pose graph's keyframes at their current poses (what a saved map keeps). Any thread.
  [[nodiscard]] std::vector<KeyframePose> keyframes() const { return localizer_.keyframes(); }
  /// Waits until every scan submitted so far has been registered and handed on (or dropped): what a replay
  /// as fast as possible paces on. Returns false when the worker is stopping.
  bool flush();

 private:
  void run();
  void process(ScanEvent scan);
  /// Localizes in `map` from now on (null: maps again).
  void take_up(std::shared_ptr<const LocalizationMap> map);
  /// An operator's pose estimate, searched with the latest scan: a stop-and-go scanner standing still
  /// takes no next scan, and waiting for one would leave the estimate unanswered.
  void search_with_latest_scan(const PoseEstimate& estimate);
  /// The pose graph's thread: closes loops whenever the scan path made keyframes.
  void close_loops();
  /// What the localizer did with a scan, into the status and the log.
  void report(const ScanEvent& scan, const LocalizedScan& localized);
  void report(const std::vector<RelocalizationReport>& searches);
  void report(const LocalizationHealth& health, double stamp);

  RobotState& state_;
  RegisteredScanSink sink_;
  KeyframesMovedSink keyframes_sink_;
  ScanObserver observer_;
  ImuCalibrationStore* calibration_ = nullptr;
  Localizer localizer_;
  RegistrationStatus status_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  bool busy_ = false;  // a scan taken from pending_ is being processed
  std::optional<ScanEvent> pending_;
  /// A map to localize in (or null: to map again) for the next scan to take up.
  std::optional<std::shared_ptr<const LocalizationMap>> pending_map_;
  bool localizing_ = false;  ///< a map to localize in was handed over (pose estimates need one)
  std::optional<PoseEstimate> pending_estimate_;
  bool latest_scan_kept_ = false;  ///< the localizer has a scan to search an estimate with at once
  std::size_t dropped_ = 0;
  bool stopping_ = false;
  std::size_t scans_for_the_graph_ = 0;  ///< processed scans the loop thread has not looked at
  std::condition_variable graph_wake_;
  std::thread thread_;
  std::thread loop_thread_;
};

}  // namespace strata::pipeline

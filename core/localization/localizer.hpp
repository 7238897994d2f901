#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"
#include "core/geometry/standing_gyro.hpp"
#include "core/localization/graph_localizer.hpp"
#include "core/localization/localization_health.hpp"
#include "core/localization/relocalization_tracker.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// One scan as the localizer takes it.
struct ScanToLocalize {
  PointCloud points;         ///< base frame, cleaned; deskewed in place by Localizer::localize
  std::vector<float> times;  ///< each point's time from the stamp, s (a spinning lidar's); empty: none
  double stamp = 0.0;
  std::optional<Pose2> odometry;  ///< the base's odometry at the stamp; none for a lidar alone
  Eigen::Vector3d sensor_origin = Eigen::Vector3d::Zero();  ///< base frame: where the rays start
  std::optional<GravityReading> gravity;
  std::optional<StandingGyro> standing_gyro;  ///< the gyro while the base stood since the last scan
};

/// What became of one scan.
struct LocalizedScan {
  LocalizationUpdate update;  ///< the registration's outcome (its pose before any search below)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();           ///< the base, map frame, after it all
  Eigen::Isometry3d map_from_odom = Eigen::Isometry3d::Identity();  ///< the correction from now on
  std::optional<Pose2> velocity;  ///< a lidar alone's, per second: what carries its pose between scans
  LocalizationHealth health;
  std::vector<RelocalizationReport> searches;  ///< what searches for the robot ran at this scan
  /// The keyframe `update.pose` follows, for a map rebuild to move the scan with (none without a graph).
  std::optional<KeyframeAnchor> anchor;
  /// The scan belongs in the map: registered (whole or partly) or the first. A scan fault control
  /// refused is at the guess, which would smear the map with the very error the check caught.
  [[nodiscard]] bool mappable() const {
    return !update.registration || update.correction != Correction::kNone;
  }
};

/// What a search with the latest scan did.
struct LatestScanSearch {
  double stamp = 0.0;                              ///< of the scan searched with
  std::optional<Eigen::Isometry3d> map_from_odom;  ///< the new correction, when found
  LocalizationHealth health;
  std::vector<RelocalizationReport> searches;
};

/// The localizer (docs/architecture.md 3, steps 1b-5, and 4.1): each scan deskewed, registered against
/// the recent scans or a saved map from the odometry's or the motion's guess, its pose kept or refused by
/// fault control, a keyframe for the pose graph; the state it leaves the localization in; and, in a
/// saved map, the searches that find the robot again. Scan path only, except where said.
class Localizer {
 public:
  explicit Localizer(GraphLocalizerOptions options = {},
                     const Eigen::Isometry3d& initial_map_from_odom = Eigen::Isometry3d::Identity(),
                     LocalizationHealthOptions health = {});

  /// One scan's way through localization.
  LocalizedScan localize(ScanToLocalize& scan);

  /// From the next scan on, localizes in `map` (null: maps again), and searches it for the robot.
  void localize_in(std::shared_ptr<const LocalizationMap> map);
  [[nodiscard]] bool localizing() const { return graph_.localizing(); }
  /// The robot is near `hint` now: searched for around it with the next scan.
  void search_at_next_scan(const PoseEstimate& hint) { hint_ = hint; }
  /// The same, at once with the latest scan, `hint` carried back to where the robot took it by the
  /// odometry since (`odometry_now`): a stop-and-go scanner standing still takes no next scan. None
  /// without a latest scan or a map.
  [[nodiscard]] std::optional<LatestScanSearch> search_with_latest_scan(
      const PoseEstimate& hint, const std::optional<Pose2>& odometry_now);

  /// The pose graph's work, off the scan path (GraphLocalizer::close_loops): any thread.
  bool close_loops() { return graph_.close_loops(); }
  [[nodiscard]] PoseGraphStatus graph_status() const { return graph_.status(); }
  [[nodiscard]] std::vector<KeyframePose> keyframes() const { return graph_.keyframes(); }
  void start_from_calibration(const Eigen::Vector3d& mounting, double heading_drift = 0.0) {
    graph_.start_from_calibration(mounting, heading_drift);
  }
  [[nodiscard]] std::vector<PoseGraphEdge> loops() const { return graph_.loops(); }
  [[nodiscard]] const Eigen::Vector3d& gravity_mounting() const { return graph_.gravity_mounting(); }

 private:
  /// Before the scan registers: an operator's estimate, or the places followed, judged by it.
  [[nodiscard]] std::optional<Eigen::Isometry3d> search_before_registering(const ScanToLocalize& scan);
  /// The robot is at `pose`, found by a search with `scan`: the next scans confirm it. The new correction.
  Eigen::Isometry3d place(const Eigen::Isometry3d& pose, const ScanToLocalize& scan);
  /// The state the scan leaves the localization in, with what confirms or contradicts the estimate.
  void judge(const ScanToLocalize& scan, const LocalizationUpdate& update);

  GraphLocalizer graph_;
  LocalizationHealthClassifier health_;
  std::unique_ptr<RelocalizationTracker> tracker_;  // in a saved map only
  std::optional<PoseEstimate> hint_;
  std::size_t loops_seen_ = 0;
  /// The latest scan (deskewed), what an estimate is searched with at once.
  std::optional<ScanToLocalize> latest_;
};

}  // namespace strata

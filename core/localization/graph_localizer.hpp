#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "core/localization/heading_drift.hpp"
#include "core/localization/keyframe.hpp"
#include "core/localization/keyframe_trail.hpp"
#include "core/localization/loop_closure.hpp"
#include "core/localization/pose_graph_status.hpp"
#include "core/localization/scan_to_map_localizer.hpp"
#include "core/posegraph/pose_graph.hpp"

namespace strata {

struct GraphLocalizerOptions {
  LocalizerOptions scan_matching;
  /// The prediction for scans without odometry (a lidar alone).
  ConstantVelocityOptions motion;
  /// Off: the scan-to-map localizer alone (what the benchmark compares against).
  bool pose_graph = true;
  /// A registered scan becomes a keyframe when the robot moved this far, metres, or turned this much,
  /// radians, since the last one (a stop-and-go scanner's every scan; a spinning lidar's every few).
  double keyframe_distance = 1.0;
  double keyframe_angle = 0.26;
  /// What a keyframe keeps: one point per voxel of this size, metres (docs/architecture.md 4.1: memory).
  double keyframe_voxel = 0.2;
  /// What a keyframe keeps for rebuilding the map (its scans and those since the previous keyframe): one
  /// point per voxel of this size, metres (the MLS map's cell: finer adds nothing a cell can hold; 0 keeps
  /// none and the map cannot be rebuilt).
  double keyframe_map_voxel = 0.1;
  /// The chain between consecutive keyframes: the scan matcher's relative pose, with standard deviations
  /// growing with the motion (metres and radians per metre driven on top of a floor); directions the scan
  /// matcher took from odometry get the odometry's, `odometry_sigma` per metre.
  double chain_sigma_translation = 0.02;
  double chain_sigma_rotation = 0.005;
  /// The chain's roll and pitch: scan matching keeps the tilt between keyframes to a few hundredths of a
  /// degree (median; a tenth or two at worst), where each keyframe's gravity reading is off by 0.1-0.6
  /// degrees. As loose as the heading, the graph took each keyframe's tilt from its own reading: floor
  /// 20 m away at heights 0.1 m apart in the rebuilt map (docs/benchmarks.md, "Far floor"). Radians, and
  /// radians per metre driven.
  double chain_sigma_tilt = 0.001;
  double chain_sigma_tilt_per_metre = 0.0002;
  double chain_sigma_per_metre = 0.01;
  /// The chain's heading, radians per metre on top of `chain_sigma_rotation`. Held to the gyro's (0.002
  /// rad and 0.0002 per metre) the campus's maxima moved by 0.1-0.2 m either way over ten seeds, no better
  /// on the whole (docs/benchmarks.md, "Ten seeds").
  double chain_sigma_rotation_per_metre = 0.001;
  double odometry_sigma = 0.05;
  LoopClosureOptions loops;
  PoseGraphOptions optimizer;
  /// The odometry's heading drift, fitted to the optimized graph and taken out of the scan path's guesses.
  HeadingDriftOptions heading_drift;
  /// Before the first loop, where the keyframes have gravity readings and the graph estimates their
  /// mounting error: the graph is optimized as keyframes come and the scan path takes its height from it,
  /// nothing else. Scan matching's tilt follows the readings, tilted by the IMU's mounting error, which the
  /// scan path learns only as the robot turns (the campus's first 200 m are straight): 0.0025 m of climb a
  /// metre put the bridge deck 0.3-0.4 m high. The graph holds its first keyframe at the start's tilt and
  /// tells the mounting error in part from there. Moving the scan path's tilt or heading too, to a graph
  /// with no loop, carried more heading error onto new ground (docs/benchmarks.md, "Height before the
  /// first loop").
  bool height_before_loops = true;
  /// Back where it drove before, once a loop closure tied this pass to the earlier one: the earlier pass's
  /// keyframes within this many metres of the robot join the scan path's local map (their points at their
  /// poses in the graph). The local map holds only the last metres driven; its far views of what lies
  /// ahead carry each scan's tilt error over their range, and the scans that follow register to them. At
  /// the campus deck's west end the pitch swung +-0.5 degrees and the height +-0.1 m over a ramp top the
  /// earlier pass had seen from near. 0: off.
  double earlier_pass_radius = 15.0;
};

/// The information of the chain edge between two consecutive keyframes `distance` metres apart
/// (translation in the older keyframe's frame, rotation in the newer's): the scan matcher's relative pose,
/// with the odometry's sigma along `from_odometry` (unit directions in the older keyframe's frame that the
/// scan matcher took from odometry), and roll and pitch firmer than heading (GraphLocalizerOptions).
[[nodiscard]] PoseInformation chain_information(const GraphLocalizerOptions& options, double distance,
                                                std::span<const Eigen::Vector3d> from_odometry = {});

/// Localization that stays consistent (docs/architecture.md 4.1): the scan-to-map localizer on the scan
/// path, and behind it a pose graph over keyframes whose loop closures, found and optimized off the scan
/// path, correct its drift. add_scan() never waits for the graph; close_loops() does the slow part and
/// may run on another thread: its correction reaches the scan path at the next add_scan().
class GraphLocalizer {
 public:
  explicit GraphLocalizer(GraphLocalizerOptions options = {},
                          const Eigen::Isometry3d& initial_map_from_odom = Eigen::Isometry3d::Identity());

  /// The scan path: `points` in the base frame, cleaned; `odometry` the wheel odometry at the scan, none
  /// for a base without (a lidar alone: the motion since the last scans is carried on instead, and the
  /// update's map_from_odom is the pose: the correction of an odometry that stays at the origin);
  /// `sensor_origin` where the sensor was in the base frame (the rays of a map rebuild start there);
  /// `gravity` which way was up, from the base's IMU: it levels the scan path and, as an attitude prior
  /// on the keyframe, the pose graph; `standing_gyro` what its gyro read while the base stood since the
  /// last scan: the odometry's heading drift, measured (StandingGyroDrift).
  LocalizationUpdate add_scan(const PointCloud& points, const std::optional<Pose2>& odometry,
                              double stamp = 0.0,
                              const Eigen::Vector3d& sensor_origin = Eigen::Vector3d::Zero(),
                              const std::optional<GravityReading>& gravity = std::nullopt,
                              const std::optional<StandingGyro>& standing_gyro = std::nullopt);

  /// How the base moved while the scan at `stamp` was taken, per second in its own frame (what deskew()
  /// takes): the odometry since the last scan, or for a base without the constant velocity model's. None
  /// before there is one (the first scan; a gap of more than a second since the last).
  [[nodiscard]] std::optional<Pose2> velocity(const std::optional<Pose2>& odometry, double stamp) const;
  /// The revolution's `points` (base frame, one time each from the stamp, as points_in_base gives them)
  /// moved to where they were at `stamp`, with velocity(); left as measured before there is one.
  void deskew(PointCloud& points, std::span<const float> times, const std::optional<Pose2>& odometry,
              double stamp) const;

  /// The background step: looks for loop closures of the keyframes made since the last call and, when
  /// it finds one, optimizes the graph. True when the estimates changed: a loop closed, or before the
  /// first the keyframes took the graph's heights (height_before_loops). Safe to call from another
  /// thread than add_scan.
  bool close_loops();

  /// From the next scan on, localizes in a saved map (ScanToMapLocalizer::localize_in) and makes no
  /// keyframes: the saved map is fixed and drift cannot build up against it. Null: back to mapping. Either
  /// way the pose graph starts anew: its keyframes were in the frame of the map that was replaced.
  /// On the scan path's thread.
  void localize_in(std::shared_ptr<const LocalizationMap> map);
  [[nodiscard]] bool localizing() const { return scan_matching_.localizing(); }
  /// The robot is at `pose` (map frame) for `odometry` (none: a base without; then at `stamp`): found by
  /// a search (Relocalizer). The next scan starts from there. On the scan path's thread. Returns the new
  /// map <- odometry correction (as LocalizationUpdate::map_from_odom: the pose itself without odometry).
  Eigen::Isometry3d place(const Eigen::Isometry3d& pose, const std::optional<Pose2>& odometry, double stamp);

  [[nodiscard]] PoseGraphStatus status() const;
  /// What a run before this one learnt of the base's IMU: its accelerometer's mounting error (a rotation
  /// vector in the base frame, radians; z ignored) and the odometry's heading drift (radians per second of
  /// motion, as the status has it). The scan path levels with the mounting error from its next scan and
  /// the graph starts its estimate there; both go on learning. The scan path learns the mounting error
  /// only as the robot turns, so a campus run's height was 0.12 m off on average over ten seeds, 0.07 m
  /// with it known from the start (docs/benchmarks.md, "Ten seeds"). Any thread.
  void start_from_calibration(const Eigen::Vector3d& mounting, double heading_drift = 0.0);
  /// The gravity reading's mounting error the scan path levels with (ScanToMapLocalizer::
  /// gravity_mounting), for the live pose's tilt. On the scan path's thread.
  [[nodiscard]] const Eigen::Vector3d& gravity_mounting() const { return scan_matching_.gravity_mounting(); }
  /// The keyframes and their current pose estimates (map frame), oldest first, for rebuilding the map.
  [[nodiscard]] std::vector<KeyframePose> keyframes() const;
  /// The newest keyframe and its pose in the scan path's frame as it is now: what the scan just added
  /// maps after (KeyframeAnchor). None without a pose graph or before its first keyframe. On the scan
  /// path's thread.
  [[nodiscard]] std::optional<KeyframeAnchor> anchor() const;
  /// The loop closures in the graph (their `from` and `to` index keyframes()), for judging what they
  /// measured (strata_localization_bench).
  [[nodiscard]] std::vector<PoseGraphEdge> loops() const;

 private:
  /// Takes the gyro's standing reading: true when it tells the odometry's heading drift by itself.
  bool take_standing_gyro(const std::optional<Pose2>& odometry,
                          const std::optional<StandingGyro>& standing_gyro);
  /// Takes what the last optimization left for the scan path (its correction, the heading drift where the
  /// gyro does not tell it, the IMU's mounting error): true when the map frame moved.
  bool take_graph_corrections(bool drift_measured);
  /// Registers a scan from the odometry's guess, its heading drift taken out, with the scans' own
  /// motion as the second guess.
  LocalizationUpdate register_with_odometry(const PointCloud& points, const Pose2& odometry, double stamp,
                                            const std::optional<GravityReading>& gravity,
                                            const std::optional<StandingGyro>& standing_gyro, bool map_moved);
  /// Registers a lidar alone's scan from its constant velocity prediction.
  LocalizationUpdate register_alone(const PointCloud& points, double stamp,
                                    const std::optional<GravityReading>& gravity, bool map_moved);
  /// The newest keyframe's height in `graph` (close_loops' copy) optimized in place, where
  /// height_before_loops applies and enough keyframes came since the graph had `optimized_at`.
  [[nodiscard]] std::optional<double> height_before_loops(PoseGraph& graph, std::size_t optimized_at) const;
  /// A keyframe of an earlier pass and its pose in the scan path's frame.
  struct EarlierKeyframe {
    KeyframePtr keyframe;
    Eigen::Isometry3d pose;
  };
  /// The earlier pass's keyframes near the robot join the local map (GraphLocalizerOptions::
  /// earlier_pass_radius): each once while its points can still be in it, a few a scan.
  void join_earlier_pass();
  [[nodiscard]] std::vector<EarlierKeyframe> earlier_pass_to_join();
  static constexpr std::size_t kEarlierKeyframesPerScan = 4;
  void add_keyframe(const PointCloud& points, const LocalizationUpdate& update, double stamp,
                    const Eigen::Vector3d& sensor_origin, const std::optional<GravityReading>& gravity);

  GraphLocalizerOptions options_;
  ScanToMapLocalizer scan_matching_;   // scan path only
  ConstantVelocityPrediction motion_;  // scan path only: the odometry of scans that come without
  /// Scan path only: for scans with odometry, the motion of the registered scans, the second guess for a
  /// scan rejected for a jump from its odometry (ScanToMapLocalizer::add_scan).
  ConstantVelocityPrediction scan_motion_;
  KeyframeTrail trail_;  // scan path only: the scans the next keyframe keeps for the map
  /// Scan path only: the odometry's heading drift, rad/s of motion, taken out of its guesses (the pose
  /// graph's fit, or the gyro's standing reading where there is one); its turns summed (unwrapped) and its
  /// seconds of motion since the start, for the keyframes' HeadingSample.
  double heading_drift_ = 0.0;
  StandingGyroDrift standing_drift_;
  double odometry_heading_ = 0.0;
  double moving_seconds_ = 0.0;

  /// Everything below. The scan path writes keyframes_ and last_keyframe_frontend_ under it and may read
  /// them without it (it is their only writer); other threads read them under it.
  mutable std::mutex mutex_;
  std::vector<KeyframePtr> keyframes_;
  PoseGraph graph_;
  /// The scan matcher's pose of the last keyframe, in the scan matcher's current frame: the chain's
  /// relative measurement starts there.
  Eigen::Isometry3d last_keyframe_frontend_ = Eigen::Isometry3d::Identity();
  std::size_t height_optimized_at_ = 0;  ///< the graph's size at the last height_before_loops
  std::size_t searched_ = 0;             ///< keyframes looked at for loops so far
  /// Counts the graph's restarts: an optimization of a graph since replaced is thrown away.
  std::uint64_t generation_ = 0;
  /// Scan path only: per keyframe, the metres driven when its points last joined the local map.
  std::vector<std::optional<double>> joined_;
  bool placed_ = false;  // scan path only: place() moved the estimate since the last scan
  struct OdometryAt {
    double stamp = 0.0;
    Pose2 odometry;
  };
  std::optional<OdometryAt> last_odometry_;  // scan path only: the last scan's, for velocity()
  /// map <- scan matcher correction from the last optimization, not yet applied on the scan path.
  std::optional<Eigen::Isometry3d> pending_correction_;
  /// The heading drift fitted after the last optimization, not yet taken by the scan path.
  std::optional<double> pending_heading_drift_;
  /// The scan path takes the heading drift from the gyro's standing reading: the status reports that one.
  bool heading_drift_measured_ = false;
  /// The gravity reading's mounting error estimated by the last optimization, not yet taken by the scan path.
  std::optional<Eigen::Vector3d> pending_mounting_;
  PoseGraphStatus status_;
};

}  // namespace strata

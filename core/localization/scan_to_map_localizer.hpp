#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <numbers>
#include <optional>
#include <string_view>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"
#include "core/localization/constant_velocity.hpp"
#include "core/localization/global_pose.hpp"
#include "core/localization/gravity_leveling.hpp"
#include "core/localization/local_map.hpp"
#include "core/localization/localization_map.hpp"
#include "core/points/point_cloud.hpp"
#include "core/registration/register_scan.hpp"

namespace strata {

/// What the scan's guess came from.
enum class GuessSource {
  kOdometry,    ///< the base's own odometry (wheels, gyro): measured, independent of the scan
  kPrediction,  ///< a motion model over earlier scans (ConstantVelocityPrediction): nothing independent
};

/// A lidar alone's guess carries the last turn on (ConstantVelocityPrediction): where a sharp turn between
/// two scans starts or stops, it is tens of degrees off, and ICP from it can slide into a wrong place that
/// still passes fault control. Such a match pairs few of the scan's points: on a real walk through a
/// building (BALM, every other scan: turns of up to 58 degrees) 44 % against 97 % for the right one, where
/// every right match paired 58 % or more. So below `poor_pairing` the registration is tried again from the
/// guess turned about gravity's axis by each of `turns` the prediction may have missed (GuessUncertainty's
/// rotation: what the angular acceleration can do in the time since the last scan, at least `from`: a
/// 10 Hz lidar's scans are too close for a turn to hide, and the searches would cost it six registrations
/// a scan where a car's scans pair poorly), and the match that pairs the most points is taken, if it pairs
/// `clearly_more` (docs/benchmarks.md, "Real lidar sequences").
struct TurnSearchOptions {
  double poor_pairing = 0.75;                                           ///< share of the scan's points
  double from = 0.25;                                                   ///< radians, 14 degrees
  double clearly_more = 0.15;                                           ///< share of the scan's points
  std::vector<double> turns = {-1.05, -0.70, -0.35, 0.35, 0.70, 1.05};  ///< radians: 20, 40, 60 degrees
};

struct LocalizerOptions {
  RegistrationOptions registration = default_registration();
  /// The model set: what the last this many registered scans reached, and what the sensor passed in the
  /// last `local_map_metres` (LocalMap: a 10 Hz lidar's 10 scans are one second).
  std::size_t local_map_scans = 10;
  double local_map_metres = 20.0;
  double local_map_voxel = 0.1;  ///< metres; the model set keeps one point per voxel of this size
  /// Below this normal-matrix eigenvalue a direction (a corridor's axis) is taken from odometry and the rest
  /// from ICP; above the fault check's hard limit, as ICP slides along a corridor well before it is
  /// rejected (well-constrained real scans: docs/benchmarks.md, ICP). 0.08 rather than 0.05: on the
  /// campus bridge deck a 10 Hz lidar's revolutions held 0.048-0.056 along the way, and ICP against the
  /// last revolutions' ground rings held the robot back 6 cm a revolution until it was 16 m behind
  /// (docs/benchmarks.md, "The lidar on the bridge deck").
  double weak_direction_guard = 0.08;
  /// Likewise for rotation (normalised eigenvalues): about an axis no surface resists (the vertical, over
  /// open ground), the turn is taken from odometry.
  double weak_rotation_guard = 0.02;
  /// Where the translation is degenerate (a partial scan), ICP's turn about the vertical is weighed against
  /// the measured odometry's (gyro-aided), which is good for the short term and walks with the gyro's bias
  /// over the long. The weight: `sliding_yaw_weight`, times how much the scan's surfaces resist turning
  /// (none at `weak_rotation_guard`, over open ground, where ICP's yaw steps 0.3-2.5 degrees where the gyro
  /// drifts 0.03: docs/benchmarks.md, "Heading on open ground"; all from `sliding_yaw_full_information`,
  /// the rotation information about the vertical, normalised as the eigenvalues are), times 1 - exp(-d /
  /// `sliding_yaw_distance`) for the d metres driven since the last scan: a stop-and-go scanner's scans
  /// 2 m apart take 86 % of ICP's turn, a 10 Hz lidar's revolutions 8 cm apart 8 %, averaging their noise.
  /// Walls then hold the heading a gyro's bias walks: campus 1600 s tilting max 0.93 / 0.91 / 0.72 ->
  /// 0.46 / 0.35 / 0.40 m, campus 800 s lidar 0.27 -> 0.26 m, where taking all of ICP's turn made it 0.36
  /// (docs/benchmarks.md, "The partial scans' heading"). Not for a lidar alone, whose guess is a
  /// prediction. 0: the odometry's heading, always.
  double sliding_yaw_weight = 1.0;
  double sliding_yaw_full_information = 0.1;
  double sliding_yaw_distance = 1.0;  // metres
  /// ICP turning a partial scan further than this from the guess found a false minimum, not the gyro's
  /// drift (hundredths of a degree a scan): the odometry's heading stands. Over the campus bridge deck
  /// such scans turned 2-10 degrees.
  double sliding_yaw_max_change = 1.0 * std::numbers::pi / 180.0;  // radians
  /// Gravity readings against scan matching's tilt (GravityLeveling).
  GravityLevelingOptions gravity;
  /// A lidar alone's sharp turns the prediction missed.
  TurnSearchOptions turn_search;

  /// Scan-to-map registration: the target is already in the map frame, so nothing may be cropped around
  /// its origin (the caller crops each scan around its own sensor). Point-to-plane: against a local map the
  /// normals are good, and over the simulated runs it drifts far less than point-to-point, which slides on
  /// ground seen from two places (docs/benchmarks.md, localization).
  static RegistrationOptions default_registration() {
    RegistrationOptions options;
    options.min_range = 0.0;
    options.icp.metric = IcpMetric::kPointToPlane;
    // Point-to-plane settles in few steps, so the thesis's MSE stop serves; the scan pairs' thinner coarse
    // source and step stops are unmeasured here. Every pair goes into the degeneracy check: its
    // eigenvalues decide which directions odometry supplies, and the local map's normals are mostly
    // estimated already. The fine stage's source at 0.2 m rather than 0.3 m: the 3DTK scans land 7.8
    // instead of 11.4 cm from the reference, and the campus map's doubled walls (rebuilt, p95) shrink from
    // 0.54 to 0.43 m (docs/benchmarks.md, "The source of the fine stage"). The coarse stage with 300 of
    // the points: it only has to bring the guess within the fine stage's bound, which a third of them do
    // as well, and its wide searches were most of the pairing's cost (docs/benchmarks.md, "The coarse
    // stage's budget").
    options.stages = {
        {.max_correspondence_distance = 1.0,
         .source_voxel_size = 0.3,
         .max_source_points = 300,
         .mse_change_threshold = 1e-5,
         .max_iterations = 30},
        {.max_correspondence_distance = 0.25,
         .source_voxel_size = 0.2,
         .mse_change_threshold = 1e-5,
         .max_iterations = 30},
    };
    options.max_constraint_pairs = 0;
    // A 32-beam lidar's revolution in real time on one core (<= 50 ms with mapping): 2,000 of its 10,000
    // points at 0.3 m, or of more at the fine stage's 0.2 m, register as closely (docs/benchmarks.md,
    // "Real captures"). 1,000 rather than 2,000: a 16-beam lidar's scan costs a fifth less, and the
    // campus lidar and the real sequences land as closely (docs/benchmarks.md, "The source budget and the
    // coarse stage").
    options.max_source_points = 1000;
    // The pairing's searches and the new target points' normals on two threads: the same registration,
    // median 12.7 -> 9.4-10.7 ms on the campus (docs/benchmarks.md, "The scan path on two threads"). More
    // would compete with the mapping and the loop closure, which have threads of their own.
    options.icp.threads = 2;
    return options;
  }
};

/// How much of a registration was used.
enum class Correction {
  kNone,     ///< the first scan, or fault control rejected the result: the odometry guess stands
  kPartial,  ///< degenerate geometry: ICP's rotation and constrained directions, odometry along the weak one
  kFull,     ///< the registration as it came
};
[[nodiscard]] std::string_view to_string(Correction correction);

/// The outcome of one scan: where the robot was when it took it, and the map <- odometry correction
/// that carries the pose forward until the next scan.
struct LocalizationUpdate {
  Correction correction = Correction::kNone;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();           ///< base in the map frame
  Eigen::Isometry3d map_from_odom = Eigen::Isometry3d::Identity();  ///< the correction after this scan
  std::optional<RegistrationResult> registration;                   ///< none for the first scan
  /// For a partial correction, what odometry supplied (map frame, unit vectors): the directions along
  /// which the position, and the axes about which the turn, came from odometry. Empty otherwise.
  std::vector<Eigen::Vector3d> odometry_directions;
  std::vector<Eigen::Vector3d> odometry_axes;
  /// The scan's gravity reading without the IMU's learnt mounting error (none without a reading
  /// GravityLeveling::usable takes): what the pose graph's attitude prior takes.
  std::optional<GravityReading> gravity;
  /// Rejected for a jump from the odometry guess, and registered again from the second guess (the scans'
  /// own motion), which found the same pose: the odometry was off (wheels slipping), not the match.
  bool retried = false;
  /// How far off the guess may have been where it was the motion's prediction (a lidar alone), as the
  /// jump limits were widened by it; none for odometry's.
  std::optional<GuessUncertainty> guess_uncertainty;
  /// A lidar alone's prediction matched poorly, and registration from the guess turned by this much about
  /// gravity's axis (radians) matched clearly better: a sharp turn the prediction did not foresee.
  std::optional<double> turn_found;
};

/// Localization by scan matching (thesis chapter 4, with a local map as the model set): each scan is
/// registered onto the last few registered scans, starting from the odometry guess; an accepted result
/// corrects the global pose (eqs. 4.13-4.16), a rejected one keeps the odometry guess.
class ScanToMapLocalizer {
 public:
  /// `initial_map_from_odom` places the odometry frame in the map: where the robot starts (identity: the
  /// map is the odometry frame at the start).
  explicit ScanToMapLocalizer(LocalizerOptions options = {},
                              const Eigen::Isometry3d& initial_map_from_odom = Eigen::Isometry3d::Identity());

  /// `points` in the robot's base frame, already cleaned (no max-range readings, no self-returns);
  /// `odometry` the wheel odometry pose when the scan was taken; `gravity` which way was up meanwhile,
  /// when the base has an IMU: it sets the guess's tilt and levels the result (GravityLeveling);
  /// `source` whether `odometry` was measured or predicted from the scans alone (a lidar without a base),
  /// which knows nothing the scan does not; `uncertainty` how much farther than usual the guess may be
  /// off (a lidar alone before its speed is known): the jump limits widen by it. `second_guess` (map frame):
  /// where the scans' own motion puts the robot; a scan rejected for a jump from the odometry guess is
  /// registered again from there, and taken if that lands where the first registration did and within
  /// the limits of the second guess. `heading_drift` (radians) turns the odometry guess about the vertical:
  /// the odometry's own heading drift since the last scan, where it is known (HeadingDrift).
  LocalizationUpdate add_scan(const PointCloud& points, const Pose2& odometry,
                              const std::optional<GravityReading>& gravity = std::nullopt,
                              GuessSource source = GuessSource::kOdometry,
                              const std::optional<GuessUncertainty>& uncertainty = std::nullopt,
                              const std::optional<Eigen::Isometry3d>& second_guess = std::nullopt,
                              double heading_drift = 0.0);

  /// The current estimate for an odometry pose: the latest correction applied to it.
  [[nodiscard]] Eigen::Isometry3d pose(const Pose2& odometry) const {
    return global_.pose_isometry(odometry);
  }
  [[nodiscard]] const Eigen::Isometry3d& map_from_odom() const { return global_.correction(); }

  /// Moves the estimate by `correction` (new map <- old map), as a pose graph optimization asks: the
  /// global pose and the local map follow, so the next scan registers where the graph put the robot.
  void correct(const Eigen::Isometry3d& correction);
  /// Points an earlier pass saw (`points` and the `sensor` in a keyframe's frame, `pose` the keyframe's in
  /// the map frame) join the local map (LocalMap::join); nothing while localizing in a saved map.
  void join_local_map(const PointCloud& points, const Eigen::Isometry3d& pose,
                      const Eigen::Vector3d& sensor) {
    if (!localizing())
      local_map_.join(points, pose, sensor);
  }
  /// The gravity reading's mounting error as the pose graph estimated it (GravityLeveling::set_bias).
  void set_gravity_mounting(const Eigen::Vector3d& mounting) { leveling_.set_bias(mounting); }
  /// The mounting error the readings are levelled with now: the pose graph's estimate and what turning
  /// has taught since (a rotation vector in the base frame, radians).
  [[nodiscard]] const Eigen::Vector3d& gravity_mounting() const { return leveling_.bias(); }

  /// From the next scan on, registers against `map` (a saved map's points, map frame) instead of the
  /// recent scans, and keeps no local map: the saved map is fixed, and the estimate cannot drift from it
  /// (docs/architecture.md 4.1, "Localizing in a saved map"). Indexes the whole map here, once. Null: back
  /// to the recent scans, starting from the next one.
  void localize_in(std::shared_ptr<const LocalizationMap> map);
  [[nodiscard]] bool localizing() const { return saved_map_ != nullptr; }

  /// Where the sensor is in the base frame (the local map keeps where each point was seen from).
  void set_sensor_origin(const Eigen::Vector3d& origin) { sensor_origin_ = origin; }

 private:
  /// Registers the scan from `guess` against the local map or the saved map, with the searches that
  /// correct a bad guess: a lidar alone's missed turn, an odometry jump confirmed from the second guess.
  /// `guess` becomes what the weak directions are to come from; `update` learns what was retried.
  RegistrationResult register_from(const PointCloud& points, Eigen::Isometry3d& guess, GuessSource source,
                                   const std::optional<GuessUncertainty>& uncertainty,
                                   const std::optional<Eigen::Isometry3d>& second_guess,
                                   LocalizationUpdate& update);
  /// The turn search (TurnSearchOptions): the turn whose match replaced `result`, if one did.
  std::optional<double> search_turns(ScanRegistration& registration, const PointCloud& points,
                                     const Eigen::Isometry3d& guess, const FaultLimits& limits,
                                     double missable_turn, RegistrationResult& result) const;
  /// What of `result` the pose takes: all of it, all but the weak directions (taken from `guess`), or
  /// nothing (fault control refused it).
  void use_registration(RegistrationResult result, const Eigen::Isometry3d& guess, GuessSource source,
                        bool guess_informs, std::optional<double> moved, LocalizationUpdate& update) const;

  LocalizerOptions options_;
  ScanRegistration registration_;
  GlobalPose global_;
  Eigen::Vector3d sensor_origin_ = Eigen::Vector3d::Zero();
  LocalMap local_map_;  // map frame
  GravityLeveling leveling_;
  std::optional<Pose2> last_odometry_;  // the last scan's: how far the guess's tilt may be stale
  std::shared_ptr<const LocalizationMap> saved_map_;      // none while mapping
  std::unique_ptr<ScanRegistration> saved_registration_;  // indexes saved_map_ (and keeps its normals)
};

}  // namespace strata

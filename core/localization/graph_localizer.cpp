#include "core/localization/graph_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/points/deskew.hpp"
#include "core/points/voxel_downsample.hpp"

namespace strata {
namespace {

/// One point per `voxel` of a scan, from its `map_points` (one per finer `map_voxel`, fewer to hash) when
/// the voxels nest: the first point of a coarse voxel is then the first of its finer one, the same points.
PointCloud keyframe_points(const PointCloud& points, const PointCloud& map_points, double map_voxel,
                           double voxel) {
  const double ratio = map_voxel > 0.0 ? voxel / map_voxel : 0.0;
  const bool nested = ratio >= 1.0 && std::abs(ratio - std::round(ratio)) < 1e-9;
  return voxel_downsample(nested ? map_points : points, voxel);
}

/// The odometry's heading drift over the keyframes at their poses in `graph` (HeadingDrift).
std::optional<double> heading_drift_of(const PoseGraph& graph, const std::vector<KeyframePtr>& keyframes,
                                       const HeadingDriftOptions& options) {
  std::vector<HeadingSample> headings;
  for (std::size_t i = 0; i < graph.size(); ++i)
    if (const std::optional<HeadingSample>& sample = keyframes[i]->odometry_heading; sample) {
      headings.push_back(*sample);
      headings.back().estimated_heading = heading_of(graph.pose(i));
    }
  return fit_heading_drift(headings, options);
}

}  // namespace

PoseInformation chain_information(const GraphLocalizerOptions& options, double distance,
                                  std::span<const Eigen::Vector3d> from_odometry) {
  // As sure as a scan match over that distance; where it took a direction from odometry (a corridor's
  // axis), as sure as odometry.
  const double sigma_t = options.chain_sigma_translation + options.chain_sigma_per_metre * distance;
  const double sigma_r = options.chain_sigma_rotation + options.chain_sigma_rotation_per_metre * distance;
  const double sigma_odometry = options.chain_sigma_translation + options.odometry_sigma * distance;
  Eigen::Matrix3d translation = Eigen::Matrix3d::Identity() / (sigma_t * sigma_t);
  for (const Eigen::Vector3d& d : from_odometry)
    translation += (1.0 / (sigma_odometry * sigma_odometry) - 1.0 / (sigma_t * sigma_t)) * d * d.transpose();
  // Rotation errors are in the keyframe's own frame, whose x and y axes are its roll and pitch.
  const double sigma_tilt = options.chain_sigma_tilt + options.chain_sigma_tilt_per_metre * distance;
  PoseInformation information = PoseInformation::Zero();
  information.topLeftCorner<3, 3>() = translation;
  information.bottomRightCorner<3, 3>() =
      Eigen::Vector3d(1.0 / (sigma_tilt * sigma_tilt), 1.0 / (sigma_tilt * sigma_tilt),
                      1.0 / (sigma_r * sigma_r))
          .asDiagonal();
  return information;
}

GraphLocalizer::GraphLocalizer(GraphLocalizerOptions options, const Eigen::Isometry3d& initial_map_from_odom)
    : options_(std::move(options)),
      scan_matching_(options_.scan_matching, initial_map_from_odom),
      motion_(options_.motion),
      scan_motion_(options_.motion),
      trail_(options_.keyframe_map_voxel),
      standing_drift_(options_.heading_drift) {}

LocalizationUpdate GraphLocalizer::add_scan(const PointCloud& points, const std::optional<Pose2>& odometry,
                                            double stamp, const Eigen::Vector3d& sensor_origin,
                                            const std::optional<GravityReading>& gravity,
                                            const std::optional<StandingGyro>& standing_gyro) {
  const bool drift_measured = take_standing_gyro(odometry, standing_gyro);
  const bool pose_graph = options_.pose_graph && !scan_matching_.localizing();
  // The last optimization moves the scan path's frame before this scan registers in it; so does a place a
  // search found. Either is a jump the motion models must not take for a velocity.
  bool map_moved = pose_graph && take_graph_corrections(drift_measured);
  map_moved = std::exchange(placed_, false) || map_moved;
  if (pose_graph)
    join_earlier_pass();
  scan_matching_.set_sensor_origin(sensor_origin);
  const LocalizationUpdate update =
      odometry ? register_with_odometry(points, *odometry, stamp, gravity, standing_gyro, map_moved)
               : register_alone(points, stamp, gravity, map_moved);
  const bool registered = !update.registration || update.correction != Correction::kNone;
  if (pose_graph && registered)
    add_keyframe(points, update, stamp, sensor_origin, gravity);
  return update;
}

bool GraphLocalizer::take_standing_gyro(const std::optional<Pose2>& odometry,
                                        const std::optional<StandingGyro>& standing_gyro) {
  if (standing_gyro && odometry)
    standing_drift_.add(*standing_gyro);
  const std::optional<double> measured_drift = standing_drift_.drift();
  if (!measured_drift)
    return false;
  heading_drift_ = *measured_drift;
  std::lock_guard lock(mutex_);
  status_.heading_drift = *measured_drift;
  heading_drift_measured_ = true;
  return true;
}

bool GraphLocalizer::take_graph_corrections(bool drift_measured) {
  std::optional<Eigen::Isometry3d> correction;
  std::optional<Eigen::Vector3d> mounting;
  {
    std::lock_guard lock(mutex_);
    correction = std::exchange(pending_correction_, std::nullopt);
    if (correction)
      last_keyframe_frontend_ = *correction * last_keyframe_frontend_;
    // The graph's fit, where the gyro's standing reading does not tell the drift itself.
    if (pending_heading_drift_ && !drift_measured)
      heading_drift_ = *std::exchange(pending_heading_drift_, std::nullopt);
    mounting = std::exchange(pending_mounting_, std::nullopt);
  }
  if (correction)
    scan_matching_.correct(*correction);
  if (mounting)
    scan_matching_.set_gravity_mounting(*mounting);
  return correction.has_value();
}

std::vector<GraphLocalizer::EarlierKeyframe> GraphLocalizer::earlier_pass_to_join() {
  const double radius = options_.earlier_pass_radius;
  // What the local map still holds: its points older than that are gone, and the earlier pass's with them.
  const double window = std::max(options_.scan_matching.local_map_metres, radius);
  std::lock_guard lock(mutex_);  // the graph's poses move with each optimization
  if (radius <= 0.0 || keyframes_.empty())
    return {};
  const double now = keyframes_.back()->travelled;
  const bool tied = std::ranges::any_of(graph_.edges(), [&](const PoseGraphEdge& edge) {
    return edge.loop && keyframes_[std::max(edge.from, edge.to)]->travelled >= now - window;
  });
  if (!tied)
    return {};
  const std::size_t newest = keyframes_.size() - 1;
  const Eigen::Vector3d here = graph_.pose(newest).translation();
  std::vector<std::pair<double, std::size_t>> near;  // distance, keyframe
  joined_.resize(keyframes_.size());
  for (std::size_t i = 0; i < newest && keyframes_[i]->travelled < now - window; ++i) {
    const double distance = (graph_.pose(i).translation() - here).norm();
    if (distance <= radius && !(joined_[i] && now - *joined_[i] < window))
      near.emplace_back(distance, i);
  }
  // The nearest first, a few a scan: back on an earlier pass's way, tens are near at once, and joining
  // all of them held one scan 0.2 s.
  const std::size_t taken = std::min(near.size(), kEarlierKeyframesPerScan);
  std::ranges::partial_sort(near, near.begin() + static_cast<std::ptrdiff_t>(taken));
  // The graph's frame and the scan path's agree at the newest keyframe, once its correction is taken;
  // one made meanwhile is not yet.
  const Eigen::Isometry3d scan_path_from_graph = last_keyframe_frontend_ * graph_.pose(newest).inverse();
  std::vector<EarlierKeyframe> joining;
  for (std::size_t k = 0; k < taken; ++k) {
    const std::size_t i = near[k].second;
    joining.push_back({keyframes_[i], scan_path_from_graph * graph_.pose(i)});
    joined_[i] = now;
  }
  status_.earlier_pass_joins += joining.size();
  return joining;
}

void GraphLocalizer::join_earlier_pass() {
  // Their scans at the map's voxel, the local map's too: the keyframe's own points, thinned for loop
  // closures, held the crest half as well (docs/benchmarks.md, "The earlier pass").
  PointCloud points;
  for (const EarlierKeyframe& earlier : earlier_pass_to_join())
    for (const KeyframeScan& scan : earlier.keyframe->scans) {
      points.assign(scan.points.size(), Eigen::Vector3d::Zero());
      std::ranges::transform(scan.points, points.begin(),
                             [](const Eigen::Vector3f& p) { return p.cast<double>(); });
      scan_matching_.join_local_map(points, earlier.pose, scan.sensor_origin.cast<double>());
    }
}

LocalizationUpdate GraphLocalizer::register_with_odometry(const PointCloud& points, const Pose2& odometry,
                                                          double stamp,
                                                          const std::optional<GravityReading>& gravity,
                                                          const std::optional<StandingGyro>& standing_gyro,
                                                          bool map_moved) {
  // Seconds of motion since the last scan, over which the odometry's heading drifted: none where it
  // stood still (a base standing holds its heading), and less the time it stood where the gyro says.
  double moving = 0.0;
  if (last_odometry_) {
    const Pose2 moved = odometry.relative_to(last_odometry_->odometry);
    if (std::hypot(moved.x, moved.y) > 1e-4 || std::abs(moved.theta) > 1e-5)
      moving = std::max(0.0, stamp - last_odometry_->stamp - (standing_gyro ? standing_gyro->seconds : 0.0));
    odometry_heading_ += moved.theta;
  } else {
    odometry_heading_ = odometry.theta;
  }
  moving_seconds_ += moving;
  last_odometry_ = OdometryAt{stamp, odometry};
  // Not across a correction of the map frame: the last pose would be in the old one.
  const std::optional<Eigen::Isometry3d> second_guess =
      map_moved ? std::nullopt : scan_motion_.predict_pose(stamp);
  LocalizationUpdate update = scan_matching_.add_scan(points, odometry, gravity, GuessSource::kOdometry,
                                                      std::nullopt, second_guess, heading_drift_ * moving);
  scan_motion_.update(stamp, odometry, update.pose,
                      update.registration && update.correction != Correction::kNone, map_moved);
  return update;
}

LocalizationUpdate GraphLocalizer::register_alone(const PointCloud& points, double stamp,
                                                  const std::optional<GravityReading>& gravity,
                                                  bool map_moved) {
  const Pose2 predicted = motion_.predict(stamp);
  LocalizationUpdate update = scan_matching_.add_scan(points, predicted, gravity, GuessSource::kPrediction,
                                                      motion_.uncertainty(stamp));
  motion_.update(stamp, predicted, update.pose, update.registration && update.correction != Correction::kNone,
                 map_moved);
  // The correction is against the prediction's frame, which no one else has: to whoever carries the
  // base's missing (constant, identity) odometry with it, it must give the scan's pose.
  update.map_from_odom = update.pose;
  return update;
}

std::optional<Pose2> GraphLocalizer::velocity(const std::optional<Pose2>& odometry, double stamp) const {
  if (!odometry)
    return motion_.velocity();
  // Older than a second, the last scan says little of the motion during this one.
  constexpr double kMaxGap = 1.0;
  if (!last_odometry_ || stamp <= last_odometry_->stamp || stamp - last_odometry_->stamp > kMaxGap)
    return std::nullopt;
  const double dt = stamp - last_odometry_->stamp;
  const Pose2 moved = odometry->relative_to(last_odometry_->odometry);
  return Pose2{moved.x / dt, moved.y / dt, moved.theta / dt};
}

void GraphLocalizer::deskew(PointCloud& points, std::span<const float> times,
                            const std::optional<Pose2>& odometry, double stamp) const {
  if (const std::optional<Pose2> moving = velocity(odometry, stamp))
    strata::deskew(points, times, *moving);
}

void GraphLocalizer::add_keyframe(const PointCloud& points, const LocalizationUpdate& update, double stamp,
                                  const Eigen::Vector3d& sensor_origin,
                                  const std::optional<GravityReading>& gravity) {
  // Read without the lock: the scan path is the only writer of last_keyframe_frontend_ and keyframes_,
  // and this is the scan path. So the thinning below, the costly part, runs before the lock the pose
  // graph's thread waits on.
  const Eigen::Isometry3d relative = last_keyframe_frontend_.inverse() * update.pose;
  const double distance = relative.translation().norm();
  const double angle = Eigen::AngleAxisd(relative.linear()).angle();
  if (!keyframes_.empty() && distance < options_.keyframe_distance && angle < options_.keyframe_angle) {
    trail_.add(points, sensor_origin, relative);
    return;
  }
  auto keyframe = std::make_shared<Keyframe>();
  keyframe->stamp = stamp;
  const PointCloud map_points = trail_.thin(points);
  keyframe->points = keyframe_points(points, map_points, trail_.voxel(), options_.keyframe_voxel);
  keyframe->scans = trail_.close(map_points, sensor_origin, relative);
  keyframe->mapped_pose = update.pose;
  keyframe->gravity = update.gravity;
  if (last_odometry_)  // the base's odometry, not a prediction: its drift is what HeadingDrift fits
    keyframe->odometry_heading =
        HeadingSample{.seconds = moving_seconds_, .odometry_heading = odometry_heading_};

  std::lock_guard lock(mutex_);
  keyframe->travelled = keyframes_.empty() ? 0.0 : keyframes_.back()->travelled + distance;
  if (keyframes_.empty()) {
    graph_.add_node(update.pose);
  } else {
    const std::size_t previous = graph_.size() - 1;
    const std::size_t node = graph_.add_node(graph_.pose(previous) * relative);
    PoseGraphEdge chain;
    chain.from = previous;
    chain.to = node;
    chain.measurement = relative;
    // Directions the scan matcher took from odometry, in the previous keyframe's frame.
    std::vector<Eigen::Vector3d> from_odometry;
    if (update.correction == Correction::kPartial && update.registration) {
      const TranslationConstraint& constraint = update.registration->constraint;
      for (int k = 0; k < 3; ++k)
        if (constraint.eigenvalues[k] < options_.scan_matching.weak_direction_guard)
          from_odometry.push_back(last_keyframe_frontend_.linear().transpose() *
                                  constraint.directions.col(k));
    }
    chain.information = chain_information(options_, distance, from_odometry);
    graph_.add_edge(chain);
  }
  // Gravity holds the graph's roll and pitch (and so its heights) where the chain would let them walk. The
  // reading as measured where the graph estimates its mounting error itself, from all of them; else as
  // the scan path corrected it.
  if (update.gravity && gravity) {  // the update's is set for usable readings the scan path used
    const GravityReading& reading = options_.optimizer.mounting_sigma > 0.0 ? *gravity : *update.gravity;
    graph_.add_prior({.node = graph_.size() - 1, .up_in_body = reading.up_in_base, .sigma = reading.sigma});
  }
  keyframes_.push_back(std::move(keyframe));
  last_keyframe_frontend_ = update.pose;
  status_.keyframes = keyframes_.size();
}

std::optional<double> GraphLocalizer::height_before_loops(PoseGraph& graph, std::size_t optimized_at) const {
  if (!options_.height_before_loops || graph.loop_count() > 0 || graph.prior_count() < 2 ||
      options_.optimizer.mounting_sigma <= 0.0 || graph.size() < 2)
    return std::nullopt;
  // Each keyframe's at first; a long way with no loop (thousands of keyframes) every 2 % more, so the
  // optimizations over it cost a few times one of the whole graph.
  if (graph.size() < optimized_at + std::max<std::size_t>(1, optimized_at / 50))
    return std::nullopt;
  const PoseGraphSummary summary = graph.optimize(options_.optimizer);
  if (!summary.solved)
    return std::nullopt;
  const double z = graph.pose(graph.size() - 1).translation().z();
  return std::isfinite(z) ? std::optional(z) : std::nullopt;
}

bool GraphLocalizer::close_loops() {
  if (!options_.pose_graph)
    return false;
  // A copy of the graph to work on: the scan path goes on adding keyframes meanwhile.
  PoseGraph graph;
  std::vector<KeyframePtr> keyframes;
  std::size_t from = 0;
  std::uint64_t generation = 0;
  std::size_t height_optimized_at = 0;
  {
    std::lock_guard lock(mutex_);
    if (searched_ == keyframes_.size())
      return false;
    generation = generation_;
    height_optimized_at = height_optimized_at_;
    graph = graph_;
    keyframes = keyframes_;
    from = searched_;
    searched_ = keyframes_.size();
  }
  std::vector<Eigen::Isometry3d> poses(graph.size());
  for (std::size_t i = 0; i < graph.size(); ++i)
    poses[i] = graph.pose(i);
  std::vector<LoopClosure> found;
  for (std::size_t newest = from; newest < keyframes.size(); ++newest) {
    if (std::optional<LoopClosure> loop =
            find_loop_closure(keyframes, poses, newest, graph.edges(), options_.loops)) {
      graph.add_edge(loop->edge);
      found.push_back(std::move(*loop));
    }
  }
  if (found.empty()) {
    // No loop yet, but scan matching's heading (where the scans' surfaces show it) against the odometry's
    // tells the drift too: before the first loop, the route's open stretches take their heading from it.
    const std::optional<double> drift = heading_drift_of(graph, keyframes, options_.heading_drift);
    const std::optional<double> height = height_before_loops(graph, height_optimized_at);
    std::lock_guard lock(mutex_);
    if (generation != generation_)
      return false;
    if (drift) {
      pending_heading_drift_ = *drift;
      if (!heading_drift_measured_)
        status_.heading_drift = *drift;
    }
    // Nothing but the height, and only while no keyframe came meanwhile: the newest frontend pose is then
    // the one the graph has last. It replaces a correction not yet taken, as a loop's does.
    if (height)
      height_optimized_at_ = graph.size();
    if (!height || graph_.size() != graph.size())
      return false;
    Eigen::Isometry3d lift = Eigen::Isometry3d::Identity();
    lift.translation().z() = *height - last_keyframe_frontend_.translation().z();
    pending_correction_ = lift;
    // The keyframes take their heights from the graph too, so that the map made of them follows the scan
    // path: the scan path lifted alone went on mapping ground it had mapped before at the new height, and
    // the plateau it had driven round came out in cells 0.05 m apart, steps with no room between them
    // (docs/benchmarks.md, "Heights before the first loop, in the map too").
    for (std::size_t i = 0; i < graph_.size(); ++i) {
      Eigen::Isometry3d pose = graph_.pose(i);
      pose.translation().z() = graph.pose(i).translation().z();
      graph_.set_pose(i, pose);
    }
    ++status_.height_optimizations;
    return true;
  }
  const PoseGraphSummary summary = graph.optimize(options_.optimizer);
  if (!summary.solved)
    return false;
  // The odometry's heading drift, from the loops' corrections spread along the way.
  const std::optional<double> drift = heading_drift_of(graph, keyframes, options_.heading_drift);

  std::lock_guard lock(mutex_);
  if (generation != generation_)
    return false;  // the graph started anew meanwhile (a map was loaded)
  // Keyframes made while optimizing follow the newest optimized one rigidly.
  const std::size_t optimized = graph.size();
  const Eigen::Isometry3d moved = graph.pose(optimized - 1) * graph_.pose(optimized - 1).inverse();
  for (std::size_t i = 0; i < graph_.size(); ++i)
    graph_.set_pose(i, i < optimized ? graph.pose(i) : moved * graph_.pose(i));
  // The loop edges that survived the optimizer's fault check join the live graph.
  for (const PoseGraphEdge& edge : graph.edges())
    if (edge.loop && std::none_of(graph_.edges().begin(), graph_.edges().end(), [&](const PoseGraphEdge& e) {
          return e.loop && e.from == edge.from && e.to == edge.to;
        }))
      graph_.add_edge(edge);
  if (drift) {
    pending_heading_drift_ = *drift;
    if (!heading_drift_measured_)
      status_.heading_drift = *drift;
  }
  graph_.set_mounting_error(graph.mounting_error());
  if (options_.optimizer.mounting_sigma > 0.0) {  // else it was held where it was, at nothing learnt
    pending_mounting_ = graph.mounting_error();
    status_.gravity_mounting = graph.mounting_error();
  }
  // The scan path's frame moves as its newest keyframe did (last_keyframe_frontend_ is in the scan path's
  // frame as it is now, before any correction still pending: this one replaces it).
  pending_correction_ = graph_.pose(graph_.size() - 1) * last_keyframe_frontend_.inverse();
  status_.loops = graph_.loop_count();
  status_.loops_dropped += summary.loops_dropped;
  ++status_.optimizations;
  status_.last_loop_stamp = keyframes[found.back().edge.to]->stamp;
  // How far the robot's estimate moves: the newest keyframe, from where the scan path has it to where the
  // graph puts it. Not the loop's own offset from its guess (found.back().correction), which the graph
  // shares out along the way: the status said 0.43 m for a loop at the campus ramp's foot that no map
  // rebuild followed, because no keyframe had moved enough to need one (issue 58).
  status_.last_correction =
      (graph_.pose(graph_.size() - 1).translation() - last_keyframe_frontend_.translation()).norm();
  status_.last_optimization_seconds = summary.seconds;
  return true;
}

void GraphLocalizer::localize_in(std::shared_ptr<const LocalizationMap> map) {
  scan_matching_.localize_in(std::move(map));
  trail_ = KeyframeTrail(options_.keyframe_map_voxel);
  joined_.clear();
  std::lock_guard lock(mutex_);
  keyframes_.clear();
  graph_ = PoseGraph();
  last_keyframe_frontend_ = Eigen::Isometry3d::Identity();
  searched_ = 0;
  height_optimized_at_ = 0;
  pending_correction_.reset();
  ++generation_;
}

Eigen::Isometry3d GraphLocalizer::place(const Eigen::Isometry3d& pose, const std::optional<Pose2>& odometry,
                                        double stamp) {
  const Pose2 at = odometry ? *odometry : motion_.predict(stamp);
  scan_matching_.correct(pose * scan_matching_.pose(at).inverse());
  placed_ = true;  // a jump the motion model must not take for a velocity
  return odometry ? scan_matching_.map_from_odom() : pose;
}

void GraphLocalizer::start_from_calibration(const Eigen::Vector3d& mounting, double heading_drift) {
  const Eigen::Vector3d tilt(mounting.x(), mounting.y(), 0.0);
  if (!tilt.allFinite() || !std::isfinite(heading_drift))
    return;
  std::lock_guard lock(mutex_);
  graph_.set_mounting_error(tilt);
  pending_mounting_ = tilt;
  status_.gravity_mounting = tilt;
  pending_heading_drift_ = heading_drift;
  status_.heading_drift = heading_drift;
}

PoseGraphStatus GraphLocalizer::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

std::vector<PoseGraphEdge> GraphLocalizer::loops() const {
  std::lock_guard lock(mutex_);
  std::vector<PoseGraphEdge> out;
  for (const PoseGraphEdge& edge : graph_.edges())
    if (edge.loop)
      out.push_back(edge);
  return out;
}

std::vector<KeyframePose> GraphLocalizer::keyframes() const {
  std::lock_guard lock(mutex_);
  std::vector<KeyframePose> out;
  out.reserve(keyframes_.size());
  for (std::size_t i = 0; i < keyframes_.size(); ++i)
    out.push_back({keyframes_[i], graph_.pose(i)});
  return out;
}

std::optional<KeyframeAnchor> GraphLocalizer::anchor() const {
  // Read without the lock: the scan path is the only writer of both.
  if (keyframes_.empty())
    return std::nullopt;
  return KeyframeAnchor{keyframes_.back(), last_keyframe_frontend_};
}

}  // namespace strata

#include "core/navigation/pure_pursuit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/geometry/angles.hpp"

namespace strata {
namespace {

/// How far the progress search looks ahead of the current segment, metres: enough to catch up after a
/// stop, short enough not to jump to a later part of the path that passes nearby (over or under).
constexpr double kSearchAhead = 3.0;
/// A later part of the path at another level is not where the robot is, however close in the plane.
constexpr double kLevelPenalty = 4.0;
/// Farther than this from the path near the progress, the robot is looked for along all of it, metres.
constexpr double kLost = 1.0;

}  // namespace

PurePursuit::PurePursuit(PurePursuitConfig config) : config_(config) {}

void PurePursuit::set_path(std::vector<Eigen::Vector3d> path) {
  path_ = std::move(path);
  along_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i)
    along_[i] = along_[i - 1] + (path_[i] - path_[i - 1]).head<2>().norm();
  progress_ = 0;
  progress_along_ = 0.0;
}

void PurePursuit::clear() {
  set_path({});
}

void PurePursuit::advance(const Eigen::Vector3d& position) {
  if (path_.size() < 2)
    return;
  // Nearest segment a little ahead of the progress; if the robot is far from all of them (it was moved,
  // or stood still while the path was replaced), the nearest of the whole rest of the path.
  for (const double window : {kSearchAhead, std::numeric_limits<double>::infinity()}) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_segment = progress_;
    double best_along = progress_along_;
    for (std::size_t i = progress_; i + 1 < path_.size(); ++i) {
      if (along_[i] > progress_along_ + window)
        break;
      const Eigen::Vector2d a = path_[i].head<2>();
      const Eigen::Vector2d ab = path_[i + 1].head<2>() - a;
      const double squared = ab.squaredNorm();
      const double t = squared > 0.0 ? std::clamp((position.head<2>() - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
      const Eigen::Vector2d closest = a + t * ab;
      const double height = path_[i].z() + t * (path_[i + 1].z() - path_[i].z());
      const double distance =
          (position.head<2>() - closest).norm() + kLevelPenalty * std::abs(position.z() - height);
      if (distance < best) {
        best = distance;
        best_segment = i;
        best_along = along_[i] + t * std::sqrt(squared);
      }
    }
    if (best_along >= progress_along_) {
      progress_ = best_segment;
      progress_along_ = best_along;
    }
    if (best <= kLost)
      return;
  }
}

Eigen::Vector2d PurePursuit::point_ahead(const Eigen::Vector3d& position, double distance) const {
  // The first path point beyond the current progress at least `distance` from the robot in the plane.
  for (std::size_t i = progress_ + 1; i < path_.size(); ++i)
    if ((path_[i].head<2>() - position.head<2>()).norm() >= distance && along_[i] >= progress_along_)
      return path_[i].head<2>();
  return path_.back().head<2>();
}

PurePursuit::Output PurePursuit::update(const Pose3& pose) {
  Output output;
  if (path_.empty()) {
    output.arrived = true;
    return output;
  }
  const Eigen::Vector3d& position = pose.position;
  advance(position);
  const double to_goal = (path_.back().head<2>() - position.head<2>()).norm();
  output.remaining = std::max(along_.back() - progress_along_, to_goal);
  const bool on_last_stretch = along_.back() - progress_along_ < config_.lookahead + config_.goal_tolerance;
  if (to_goal <= config_.goal_tolerance && on_last_stretch) {
    output.arrived = true;
    return output;
  }

  const Eigen::Vector2d target = point_ahead(position, config_.lookahead);
  const Eigen::Vector2d offset = target - position.head<2>();
  const double heading_error = wrap_angle(std::atan2(offset.y(), offset.x()) - pose.yaw);
  if (std::abs(heading_error) > config_.turn_in_place) {
    const double w =
        std::clamp(config_.turn_gain * heading_error, -config_.max_turn_rate, config_.max_turn_rate);
    output.command = {0.0, w};
    return output;
  }
  // The arc through the target: curvature 2 sin(alpha) / L.
  const double distance = std::max(offset.norm(), 1e-6);
  const double curvature = 2.0 * std::sin(heading_error) / distance;
  double v = config_.cruise_speed * (1.0 - 0.5 * std::abs(heading_error) / config_.turn_in_place);
  v = std::min(v, config_.cruise_speed * std::clamp(output.remaining / config_.slow_down, 0.0, 1.0));
  v = std::max(v, config_.min_speed);
  if (std::abs(v * curvature) > config_.max_turn_rate)
    v = config_.max_turn_rate / std::abs(curvature);  // slow down for sharp arcs rather than leave the path
  output.command = {v, v * curvature};
  return output;
}

}  // namespace strata

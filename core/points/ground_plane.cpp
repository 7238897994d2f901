#include "core/points/ground_plane.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <string>

#include "core/points/voxel_downsample.hpp"

namespace strata {
namespace {

struct Plane {
  Eigen::Vector3d normal;
  double offset = 0.0;  // n . p + offset = 0
};

std::size_t count_inliers(const std::vector<Eigen::Vector3d>& points, const Plane& plane, double distance) {
  std::size_t n = 0;
  for (const Eigen::Vector3d& p : points)
    n += std::abs(plane.normal.dot(p) + plane.offset) <= distance ? 1 : 0;
  return n;
}

/// The least-squares plane through the points within `distance` of `plane`.
Plane refit(const std::vector<Eigen::Vector3d>& points, const Plane& plane, double distance) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<const Eigen::Vector3d*> on;
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(plane.normal.dot(p) + plane.offset) <= distance) {
      on.push_back(&p);
      mean += p;
    }
  }
  if (on.size() < 3)
    return plane;
  mean /= static_cast<double>(on.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d* p : on)
    covariance += (*p - mean) * (*p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Vector3d normal = solver.eigenvectors().col(0);
  if (normal.dot(plane.normal) < 0.0)
    normal = -normal;
  return {normal, -normal.dot(mean)};
}

}  // namespace

Eigen::Isometry3d GroundPlane::sensor_to_base() const {
  const Eigen::Vector3d z = normal;
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z * z.x();
  if (x.norm() < 1e-6)  // the sensor's x points at the ground: take its y for the heading
    x = Eigen::Vector3d::UnitY() - z * z.y();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d base_from_sensor;
  base_from_sensor.row(0) = x.transpose();
  base_from_sensor.row(1) = y.transpose();
  base_from_sensor.row(2) = z.transpose();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = base_from_sensor;
  pose.translation() = Eigen::Vector3d(0.0, 0.0, height);
  return pose;
}

Eigen::Vector2d GroundPlane::tilt_deg() const {
  // The sensor's z axis seen from the base: roll about x, pitch about y.
  const Eigen::Vector3d up = sensor_to_base().linear().col(2);
  constexpr double kDeg = 180.0 / M_PI;
  return {std::atan2(-up.y(), up.z()) * kDeg, std::atan2(up.x(), up.z()) * kDeg};
}

std::optional<GroundPlane> find_ground_plane(const std::vector<Eigen::Vector3f>& points,
                                             const GroundPlaneOptions& options, std::string* why) {
  const auto fail = [why](std::string reason) -> std::optional<GroundPlane> {
    if (why != nullptr)
      *why = std::move(reason);
    return std::nullopt;
  };
  std::vector<Eigen::Vector3d> below;
  for (const Eigen::Vector3f& point : points) {
    const Eigen::Vector3d p = point.cast<double>();
    const double range = std::hypot(p.x(), p.y());
    if (p.allFinite() && p.z() <= -options.min_depth && range >= options.min_range &&
        range <= options.max_range)
      below.push_back(p);
  }
  const std::vector<Eigen::Vector3d> candidates = voxel_downsample(below, options.thinning_voxel);
  if (candidates.size() < options.min_inliers)
    return fail(std::to_string(candidates.size()) + " points below the sensor within " +
                std::to_string(static_cast<int>(options.max_range)) + " m (need " +
                std::to_string(options.min_inliers) + ")");

  // RANSAC: planes through three random candidates, nearly level, scored by their inliers.
  const double min_cos = std::cos(options.max_tilt_deg * M_PI / 180.0);
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  std::optional<Plane> best;
  std::size_t best_inliers = 0;
  for (int i = 0; i < options.iterations; ++i) {
    const Eigen::Vector3d& a = candidates[pick(random)];
    const Eigen::Vector3d& b = candidates[pick(random)];
    const Eigen::Vector3d& c = candidates[pick(random)];
    Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-6)
      continue;
    normal.normalize();
    if (normal.z() < 0.0)
      normal = -normal;
    if (normal.z() < min_cos)
      continue;
    const Plane plane{normal, -normal.dot(a)};
    const std::size_t inliers = count_inliers(candidates, plane, options.inlier_distance);
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = plane;
    }
  }
  if (!best || best_inliers < options.min_inliers)
    return fail("no level plane under the sensor holds " + std::to_string(options.min_inliers) + " of its " +
                std::to_string(candidates.size()) + " thinned points (best " + std::to_string(best_inliers) +
                ")");
  Plane plane = refit(candidates, *best, options.inlier_distance);
  plane = refit(candidates, plane, options.inlier_distance);  // once more, from the better plane's inliers
  GroundPlane ground;
  ground.normal = plane.normal;
  ground.height = plane.offset;  // n . 0 + offset: the sensor's (origin's) signed distance, up positive
  ground.inliers = count_inliers(candidates, plane, options.inlier_distance);
  ground.candidates = candidates.size();
  if (ground.height <= 0.0)
    return fail("the plane found is not under the sensor");
  return ground;
}

}  // namespace strata

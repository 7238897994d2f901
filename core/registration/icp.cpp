#include "core/registration/icp.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <span>

namespace strata {
namespace {

double kernel_weight(double residual, double scale) {
  if (scale <= 0.0)
    return 1.0;
  const double s2 = scale * scale;
  const double ratio = s2 / (s2 + residual * residual);
  return ratio * ratio;
}

/// One point-to-point step (thesis eqs. 4.3-4.10): the rigid motion that best maps the moved source points
/// onto their partners, by centroids (eq. 4.3), correlation (eq. 4.5) and the rotation solver (eq. 4.6).
Eigen::Isometry3d point_to_point_step(const PointCloud& moved, const PointCloud& target,
                                      const std::vector<Correspondence>& pairs, const IcpOptions& options) {
  // Plain least squares (no kernel) weighs every pair 1: no residuals to take, no weights to keep.
  const bool weighted = options.kernel_scale > 0.0;
  std::vector<double> weights;
  if (weighted) {
    weights.reserve(pairs.size());
    for (const Correspondence& pair : pairs)
      weights.push_back(
          kernel_weight((target[pair.target] - moved[pair.source]).norm(), options.kernel_scale));
  }
  double total_weight = 0.0;
  Eigen::Vector3d mean_d = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const double w = weighted ? weights[i] : 1.0;
    total_weight += w;
    mean_d += w * moved[pairs[i].source];
    mean_x += w * target[pairs[i].target];
  }
  mean_d /= total_weight;
  mean_x /= total_weight;
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();  // eq. 4.5 over centred pairs (eq. 4.4)
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const double w = weighted ? weights[i] : 1.0;
    s += w * (moved[pairs[i].source] - mean_d) * (target[pairs[i].target] - mean_x).transpose();
  }
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = solve_rotation(s, options.rotation_solver);
  step.translation() = mean_x - step.linear() * mean_d;  // eq. 4.10's second term
  return step;
}

/// A wall's pairs across it, fewer than this, tell no turn: they are dropped.
constexpr std::size_t kMinAcrossPairs = 10;

/// The rows of the pairs across thin walls, each wall's mean taken out: its other face is parallel to the
/// one the scan sees, at an offset no one measured, which a free offset per wall absorbs (minimised out
/// in closed form). What is left is how the wall turns.
void add_across_rows(const PointCloud& moved, const PointCloud& target, std::span<const AcrossPair> across,
                     const IcpOptions& options, Eigen::Matrix<double, 6, 6>& hessian,
                     Eigen::Matrix<double, 6, 1>& gradient) {
  struct Row {
    Eigen::Matrix<double, 6, 1> jacobian;
    double residual = 0.0;
  };
  std::map<std::uint64_t, std::vector<Row>> walls;
  for (const AcrossPair& a : across) {
    // One wall's normals all turned one way (an estimate's sign is arbitrary): its rows differ only by
    // where on the wall they are.
    const Eigen::Vector3d& n = a.normal;
    const Eigen::Vector3d& p = moved[a.pair.source];
    Row row;
    row.jacobian << n, p.cross(n);
    row.residual = n.dot(p - target[a.pair.target]);
    walls[a.surface].push_back(row);
  }
  for (const auto& [surface, rows] : walls) {
    if (rows.size() < kMinAcrossPairs)
      continue;
    Row mean;
    mean.jacobian.setZero();
    for (const Row& row : rows) {
      mean.jacobian += row.jacobian;
      mean.residual += row.residual;
    }
    mean.jacobian /= static_cast<double>(rows.size());
    mean.residual /= static_cast<double>(rows.size());
    for (const Row& row : rows) {
      const Eigen::Matrix<double, 6, 1> jacobian = row.jacobian - mean.jacobian;
      const double residual = row.residual - mean.residual;
      const double w = kernel_weight(residual, options.kernel_scale);
      hessian.noalias() += w * jacobian * jacobian.transpose();
      gradient.noalias() += w * residual * jacobian;
    }
  }
}

/// One point-to-plane Gauss-Newton step, linearised at the moved points: residual n . (p + w x p + t - x)
/// in the small rotation w and translation t.
Eigen::Isometry3d point_to_plane_step(const PointCloud& moved, const PointCloud& target, LazyNormals& normals,
                                      const std::vector<Correspondence>& pairs,
                                      std::span<const AcrossPair> across, const IcpOptions& options) {
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
  std::size_t used = 0;
  for (const Correspondence& pair : pairs) {
    const Eigen::Vector3d* n = normals.at(pair.target);
    if (n == nullptr)
      continue;
    const Eigen::Vector3d& p = moved[pair.source];
    const double residual = n->dot(p - target[pair.target]);
    Eigen::Matrix<double, 6, 1> jacobian;
    jacobian << *n, p.cross(*n);
    const double w = kernel_weight(residual, options.kernel_scale);
    hessian.noalias() += w * jacobian * jacobian.transpose();
    gradient.noalias() += w * residual * jacobian;
    ++used;
  }
  if (used < options.min_pairs)
    return Eigen::Isometry3d::Identity();
  add_across_rows(moved, target, across, options, hessian, gradient);
  const Eigen::Matrix<double, 6, 1> delta = hessian.ldlt().solve(-gradient);
  if (!delta.allFinite())
    return Eigen::Isometry3d::Identity();
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d rotation = delta.tail<3>();
  if (rotation.norm() > 0.0)
    step.linear() = Eigen::AngleAxisd(rotation.norm(), rotation.normalized()).toRotationMatrix();
  step.translation() = delta.head<3>();
  return step;
}

/// Thesis eq. 4.12 over the given pairs, with the metric's own residual.
double mean_squared_error(const PointCloud& moved, const PointCloud& target, LazyNormals* normals,
                          const std::vector<Correspondence>& pairs, IcpMetric metric) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const Correspondence& pair : pairs) {
    const Eigen::Vector3d difference = moved[pair.source] - target[pair.target];
    if (metric == IcpMetric::kPointToPlane) {
      const Eigen::Vector3d* n = normals->at(pair.target);
      if (n == nullptr)
        continue;
      const double r = n->dot(difference);
      sum += r * r;
    } else {
      sum += difference.squaredNorm();
    }
    ++count;
  }
  return count == 0 ? 0.0 : sum / static_cast<double>(count);
}

}  // namespace

IcpResult align(const PointCloud& source, const GrowingKdTree& target, LazyNormals* normals,
                const Eigen::Isometry3d& guess, const IcpOptions& options, const SurfaceSides* sides) {
  IcpResult result;
  result.transform = guess;
  const IcpMetric metric = normals == nullptr ? IcpMetric::kPointToPoint : options.metric;
  double previous_mse = std::numeric_limits<double>::infinity();
  PointCloud moved(source.size());
  PartnerSearch partners(target, source.size(), options.max_correspondence_distance, options.threads);
  std::vector<Correspondence> pairs;
  pairs.reserve(source.size());
  const bool split = sides != nullptr && normals != nullptr && options.surface_sides.enabled;
  std::vector<AcrossPair> across;
  std::vector<std::uint32_t> paired;  // the pairs' target points, for their normals
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // 1. Find closest point-pairs within the bound (Algorithm 2, steps 1-2).
    for (std::size_t i = 0; i < source.size(); ++i)
      moved[i] = result.transform * source[i];
    partners.pair(moved, pairs);
    if (metric == IcpMetric::kPointToPlane && options.threads > 1) {  // at() then finds them known
      paired.clear();
      for (const Correspondence& pair : pairs)
        paired.push_back(static_cast<std::uint32_t>(pair.target));
      normals->estimate(paired, options.threads);
    }
    if (split)
      split_across(result.transform, target.points(), *normals, *sides, options.surface_sides, pairs, across);
    if (pairs.size() < options.min_pairs)
      break;
    ++result.iterations;
    // 2. The transform that minimises the error over these pairs.
    const Eigen::Isometry3d step =
        metric == IcpMetric::kPointToPlane
            ? point_to_plane_step(moved, target.points(), *normals, pairs, across, options)
            : point_to_point_step(moved, target.points(), pairs, options);
    // 3. Apply it. The step acts on already-moved points, so it composes on the left: R <- R^ R and
    //    t <- R^ t + t^ (eqs. 4.9-4.10; eq. 4.9's printed order R R^ would not match eq. 4.10).
    result.transform = step * result.transform;
    for (const Correspondence& pair : pairs)
      moved[pair.source] = step * moved[pair.source];
    for (const AcrossPair& a : across)
      moved[a.pair.source] = step * moved[a.pair.source];
    // 4. Stop when the error has settled (eq. 4.12 and tau), or the transform has.
    const double mse = mean_squared_error(moved, target.points(), normals, pairs, metric);
    const bool small_step = step.translation().norm() < options.min_step_translation &&
                            Eigen::AngleAxisd(step.rotation()).angle() < options.min_step_rotation;
    if (std::abs(previous_mse - mse) < options.mse_change_threshold || small_step) {
      result.converged = true;
      break;
    }
    previous_mse = mse;
  }
  result.transform.makeAffine();
  // Orthonormalise: many composed steps let rounding creep into the rotation.
  result.transform.linear() = Eigen::Quaterniond(result.transform.rotation()).normalized().toRotationMatrix();
  for (std::size_t i = 0; i < source.size(); ++i)
    moved[i] = result.transform * source[i];
  partners.pair(moved, result.pairs);
  if (split)
    split_across(result.transform, target.points(), *normals, *sides, options.surface_sides, result.pairs,
                 across);
  double sum = 0.0;
  for (const Correspondence& pair : result.pairs)
    sum += (moved[pair.source] - target.points()[pair.target]).squaredNorm();
  result.rmse = result.pairs.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(result.pairs.size()));
  return result;
}

}  // namespace strata

#include "core/posegraph/pose_graph.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <memory>

namespace strata {
namespace {

/// A square root of an information matrix: L with L^T L = information, so |L r|^2 is the Mahalanobis
/// length of r. Through the eigen decomposition, so directions without information stay zero.
Eigen::Matrix<double, 6, 6> square_root(const PoseInformation& information) {
  const Eigen::SelfAdjointEigenSolver<PoseInformation> solver(0.5 * (information + information.transpose()));
  const Eigen::Matrix<double, 6, 1> roots = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return roots.asDiagonal() * solver.eigenvectors().transpose();
}

/// The error of two node estimates against a relative measurement, whitened: the translation of `to` in
/// `from`'s frame minus the measured one, and the small rotation from the measured relative rotation to
/// the estimated one (twice the vector part of the quaternion: the rotation vector for small angles).
class RelativePoseError {
 public:
  RelativePoseError(const Eigen::Isometry3d& measurement, const PoseInformation& information)
      : translation_(measurement.translation()),
        rotation_(Eigen::Quaterniond(measurement.linear()).normalized()),
        root_(square_root(information)) {}

  template <typename T>
  bool operator()(const T* from_position, const T* from_rotation, const T* to_position, const T* to_rotation,
                  T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_from(from_position);
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(from_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_to(to_position);
    const Eigen::Map<const Eigen::Quaternion<T>> q_to(to_rotation);
    const Eigen::Quaternion<T> q_from_inverse = q_from.conjugate();
    const Eigen::Quaternion<T> relative_rotation = q_from_inverse * q_to;
    const Eigen::Matrix<T, 3, 1> relative_translation = q_from_inverse * (p_to - p_from);
    const Eigen::Quaternion<T> difference = rotation_.template cast<T>().conjugate() * relative_rotation;
    Eigen::Matrix<T, 6, 1> error;
    error.template head<3>() = relative_translation - translation_.template cast<T>();
    // q and -q are one rotation: take the short way.
    const T sign = difference.w() < T(0) ? T(-1) : T(1);
    error.template tail<3>() = T(2) * sign * difference.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = root_.template cast<T>() * error;
    return true;
  }

 private:
  Eigen::Vector3d translation_;
  Eigen::Quaterniond rotation_;
  Eigen::Matrix<double, 6, 6> root_;
};

/// Which way is up in the body frame as the sensor reads it, estimated (R^T z, turned by the mounting
/// error m about the body's x and y) against measured, over its standard deviation.
class AttitudeError {
 public:
  AttitudeError(const Eigen::Vector3d& up_in_body, double sigma)
      : up_(up_in_body.normalized()), weight_(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* rotation, const T* mounting, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Matrix<T, 3, 1> up = q.conjugate() * Eigen::Matrix<T, 3, 1>(T(0), T(0), T(1));
    const T angle_axis[3] = {mounting[0], mounting[1], T(0)};
    Eigen::Matrix<T, 3, 1> read;
    ceres::AngleAxisRotatePoint(angle_axis, up.data(), read.data());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
    out = T(weight_) * (read - up_.cast<T>());
    return true;
  }

 private:
  Eigen::Vector3d up_;
  double weight_;
};

/// The mounting error's own prior: near zero, by its standard deviation.
class MountingPrior {
 public:
  explicit MountingPrior(double sigma) : weight_(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* mounting, T* residual) const {
    residual[0] = T(weight_) * mounting[0];
    residual[1] = T(weight_) * mounting[1];
    return true;
  }

 private:
  double weight_;
};

}  // namespace

std::size_t PoseGraph::add_node(const Eigen::Isometry3d& pose) {
  positions_.push_back(pose.translation());
  rotations_.push_back(Eigen::Quaterniond(pose.linear()).normalized());
  return positions_.size() - 1;
}

void PoseGraph::add_edge(const PoseGraphEdge& edge) {
  edges_.push_back(edge);
}

void PoseGraph::add_prior(const AttitudePrior& prior) {
  priors_.push_back(prior);
}

Eigen::Isometry3d PoseGraph::pose(std::size_t node) const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotations_[node].toRotationMatrix();
  pose.translation() = positions_[node];
  return pose;
}

void PoseGraph::set_pose(std::size_t node, const Eigen::Isometry3d& pose) {
  positions_[node] = pose.translation();
  rotations_[node] = Eigen::Quaterniond(pose.linear()).normalized();
}

std::size_t PoseGraph::loop_count() const {
  std::size_t loops = 0;
  for (const PoseGraphEdge& edge : edges_)
    loops += edge.loop ? 1 : 0;
  return loops;
}

double PoseGraph::residual(const PoseGraphEdge& edge) const {
  const RelativePoseError error(edge.measurement, edge.information);
  Eigen::Matrix<double, 6, 1> whitened;
  const Eigen::Vector4d from_rotation = rotations_[edge.from].coeffs();
  const Eigen::Vector4d to_rotation = rotations_[edge.to].coeffs();
  error(positions_[edge.from].data(), from_rotation.data(), positions_[edge.to].data(), to_rotation.data(),
        whitened.data());
  return whitened.norm();
}

PoseGraphSummary PoseGraph::optimize(const PoseGraphOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  PoseGraphSummary summary;
  if (positions_.size() < 2)
    return summary;
  while (true) {
    ceres::Problem problem;
    ceres::Manifold* quaternion = new ceres::EigenQuaternionManifold;  // owned by the problem
    for (std::size_t node = 0; node < positions_.size(); ++node) {
      problem.AddParameterBlock(positions_[node].data(), 3);
      problem.AddParameterBlock(rotations_[node].coeffs().data(), 4, quaternion);
    }
    for (const PoseGraphEdge& edge : edges_) {
      auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
          new RelativePoseError(edge.measurement, edge.information));
      // A loop edge's pull levels off beyond a few standard deviations (Cauchy): a false match the
      // fault check let through bends the map less while the check below finds it.
      ceres::LossFunction* loss = edge.loop ? new ceres::CauchyLoss(2.0) : nullptr;
      problem.AddResidualBlock(cost, loss, positions_[edge.from].data(),
                               rotations_[edge.from].coeffs().data(), positions_[edge.to].data(),
                               rotations_[edge.to].coeffs().data());
    }
    for (const AttitudePrior& prior : priors_) {
      auto* cost = new ceres::AutoDiffCostFunction<AttitudeError, 3, 4, 2>(
          new AttitudeError(prior.up_in_body, prior.sigma));
      problem.AddResidualBlock(cost, nullptr, rotations_[prior.node].coeffs().data(), mounting_.data());
    }
    if (!priors_.empty()) {
      if (options.mounting_sigma > 0.0)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<MountingPrior, 2, 2>(new MountingPrior(options.mounting_sigma)),
            nullptr, mounting_.data());
      else
        problem.SetParameterBlockConstant(mounting_.data());
    }
    problem.SetParameterBlockConstant(positions_[0].data());
    problem.SetParameterBlockConstant(rotations_[0].coeffs().data());

    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.num_threads = 1;  // a background job: it must not take the scan path's core
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary result;
    ceres::Solve(solver_options, &problem, &result);
    if (summary.iterations == 0)
      summary.initial_cost = result.initial_cost;
    summary.iterations += static_cast<int>(result.iterations.size());
    summary.final_cost = result.final_cost;
    summary.solved = result.IsSolutionUsable();
    if (!summary.solved)
      break;
    // Fault control for loop closures: the worst one that disagrees with everything else goes, then
    // solve again.
    std::size_t worst = edges_.size();
    double worst_residual = options.max_loop_residual;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      if (!edges_[e].loop)
        continue;
      const double r = residual(edges_[e]);
      if (r > worst_residual) {
        worst_residual = r;
        worst = e;
      }
    }
    if (worst == edges_.size())
      break;
    edges_.erase(edges_.begin() + static_cast<std::ptrdiff_t>(worst));
    ++summary.loops_dropped;
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

}  // namespace strata

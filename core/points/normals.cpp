#include "core/points/normals.hpp"

#include <Eigen/Eigenvalues>

namespace strata {

LazyNormals::LazyNormals(const KdTree& tree, std::size_t k, Estimates earlier)
    : tree_(&tree), k_(k), estimates_(std::move(earlier)) {
  estimates_.normals.resize(tree.size());
  estimates_.states.resize(tree.size(), State::kUnknown);
}

const Eigen::Vector3d* LazyNormals::at(std::size_t index) {
  State& state = estimates_.states[index];
  if (state == State::kUnknown) {
    tree_->k_nearest(tree_->points()[index], k_, neighbors_);
    state = State::kInvalid;
    if (neighbors_.size() >= 5) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const Neighbor& n : neighbors_)
        mean += tree_->points()[n.index];
      mean /= static_cast<double>(neighbors_.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const Neighbor& n : neighbors_) {
        const Eigen::Vector3d d = tree_->points()[n.index] - mean;
        covariance += d * d.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
      const Eigen::Vector3d& values = solver.eigenvalues();  // ascending
      // A surface is flat in one direction and spread in two: smallest spread well below the middle one,
      // and the middle one not negligible (k neighbours all on one scan line give a line, whose "normal"
      // is any direction across it).
      if (values(2) > 0.0 && values(0) < 0.3 * values(1) && values(1) > 0.05 * values(2)) {
        estimates_.normals[index] = solver.eigenvectors().col(0);
        state = State::kValid;
      }
    }
  }
  return state == State::kValid ? &estimates_.normals[index] : nullptr;
}

}  // namespace strata

#include "core/registration/degeneracy.hpp"

#include <Eigen/Eigenvalues>

namespace strata {

TranslationConstraint translation_constraint(const std::vector<Correspondence>& pairs, LazyNormals& normals,
                                             const PointCloud& target) {
  TranslationConstraint constraint;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Correspondence& pair : pairs) {
    if (const Eigen::Vector3d* n = normals.at(pair.target)) {
      information += *n * n->transpose();
      centroid += target[pair.target];
      ++constraint.normals_used;
    }
  }
  if (constraint.normals_used > 0) {
    centroid /= static_cast<double>(constraint.normals_used);
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();
    double spread = 0.0;
    for (const Correspondence& pair : pairs) {
      if (const Eigen::Vector3d* n = normals.at(pair.target)) {
        const Eigen::Vector3d q = target[pair.target] - centroid;
        const Eigen::Vector3d lever = q.cross(*n);
        rotation += lever * lever.transpose();
        spread += q.squaredNorm();
      }
    }
    if (spread > 0.0) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> rotation_solver(rotation / spread);
      constraint.rotation_eigenvalues = rotation_solver.eigenvalues();
      constraint.rotation_axes = rotation_solver.eigenvectors();
    }
  }
  if (constraint.normals_used == 0)
    return constraint;
  information /= static_cast<double>(constraint.normals_used);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(information);
  constraint.weakest = solver.eigenvalues()(0);
  constraint.weakest_direction = solver.eigenvectors().col(0);
  constraint.eigenvalues = solver.eigenvalues();
  constraint.directions = solver.eigenvectors();
  return constraint;
}

double rotation_information(const TranslationConstraint& constraint, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d along = constraint.rotation_axes.transpose() * axis;
  return along.cwiseProduct(along).dot(constraint.rotation_eigenvalues);
}

}  // namespace strata

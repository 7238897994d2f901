#include "core/registration/degeneracy.hpp"

#include <Eigen/Eigenvalues>

namespace strata {

TranslationConstraint translation_constraint(const std::vector<Correspondence>& pairs, LazyNormals& normals) {
  TranslationConstraint constraint;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  for (const Correspondence& pair : pairs) {
    if (const Eigen::Vector3d* n = normals.at(pair.target)) {
      information += *n * n->transpose();
      ++constraint.normals_used;
    }
  }
  if (constraint.normals_used == 0)
    return constraint;
  information /= static_cast<double>(constraint.normals_used);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(information);
  constraint.weakest = solver.eigenvalues()(0);
  constraint.weakest_direction = solver.eigenvectors().col(0);
  return constraint;
}

}  // namespace strata

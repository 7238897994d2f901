#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/points/normals.hpp"
#include "core/registration/icp.hpp"

namespace strata {

/// How well the paired surfaces pin down the translation: the eigen-decomposition of the point-to-plane
/// normal matrix (1/N) sum n_i n_i^T. Its eigenvalues sum to 1; one near 0 means no surface faces that
/// direction -- a straight corridor along its axis, an open plane within it -- so ICP's answer along it is
/// the guess plus noise.
struct TranslationConstraint {
  double weakest = 0.0;                                         ///< smallest eigenvalue, in [0, 1/3]
  Eigen::Vector3d weakest_direction = Eigen::Vector3d::Zero();  ///< its eigenvector, target frame
  std::size_t normals_used = 0;
};

[[nodiscard]] TranslationConstraint translation_constraint(const std::vector<Correspondence>& pairs,
                                                           LazyNormals& normals);

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/points/point_cloud.hpp"
#include "core/registration/icp.hpp"
#include "core/registration/normals.hpp"

namespace strata {

/// How well the paired surfaces pin down the translation: the eigen-decomposition of the point-to-plane
/// normal matrix (1/N) sum n_i n_i^T. Its eigenvalues sum to 1; one near 0 means no surface faces that
/// direction -- a straight corridor along its axis, an open plane within it -- so ICP's answer along it is
/// the guess plus noise.
struct TranslationConstraint {
  double weakest = 0.0;                                         ///< smallest eigenvalue, in [0, 1/3]
  Eigen::Vector3d weakest_direction = Eigen::Vector3d::Zero();  ///< its eigenvector, target frame
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();        ///< all three, ascending
  Eigen::Matrix3d directions = Eigen::Matrix3d::Zero();  ///< their eigenvectors (columns), target frame
  /// The same for rotation: eigen-decomposition of (1/N) sum (q_i x n_i)(q_i x n_i)^T / mean |q_i|^2, with
  /// q_i the paired target point about the pairs' centroid. Near 0 about an axis: no surface resists turning
  /// about it (open ground: the vertical axis).
  Eigen::Vector3d rotation_eigenvalues = Eigen::Vector3d::Zero();  ///< ascending
  Eigen::Matrix3d rotation_axes = Eigen::Matrix3d::Zero();         ///< eigenvectors (columns), target frame
  std::size_t normals_used = 0;
};

[[nodiscard]] TranslationConstraint translation_constraint(const std::vector<Correspondence>& pairs,
                                                           LazyNormals& normals, const PointCloud& target);

/// How much the surfaces resist turning about `axis` (a unit vector, target frame): the rotation
/// eigenvalues weighed by how much of `axis` each eigenvector holds, on the same normalised scale.
[[nodiscard]] double rotation_information(const TranslationConstraint& constraint,
                                          const Eigen::Vector3d& axis);

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <optional>

namespace strata {

// The rotation step of point-to-point ICP (thesis eqs. 4.3-4.8). Given centred pairs (d_i data, x_i model)
// and their correlation matrix S = sum d_i x_i^T (eq. 4.5), the rotation minimising sum |x_i - R d_i|^2 is
// the orthonormal polar factor of S^T -- not of S: S's own polar factor S (S^T S)^(-1/2), eq. 4.6 read
// literally, is R^T. On planar or collinear pairs S loses rank and the best orthonormal fit can be a
// reflection (det = -1); the SVD with the determinant correction is the safe reference and fallback.

/// The correlation matrix S = sum (d_i - mean_d)(x_i - mean_x)^T of thesis eq. 4.5, from sums kept while
/// pairing: `sum_dx` = sum d_i x_i^T, `mean_d`, `mean_x`, `count` = N.
[[nodiscard]] Eigen::Matrix3d correlation_from_sums(const Eigen::Matrix3d& sum_dx,
                                                    const Eigen::Vector3d& mean_d,
                                                    const Eigen::Vector3d& mean_x, double count);

/// The orthonormal polar factor U of M = U P, as U = M (M^T M)^(-1/2) with the inverse square root from the
/// Denman-Beavers iteration (eqs. 4.7-4.8). Empty when M^T M is singular or the iteration does not settle.
/// U may be a reflection: the caller decides what that means.
[[nodiscard]] std::optional<Eigen::Matrix3d> polar_factor_denman_beavers(const Eigen::Matrix3d& m);

/// The thesis's rotation solver: the polar factor of S^T. Empty when it fails or is a reflection.
[[nodiscard]] std::optional<Eigen::Matrix3d> rotation_by_polar_decomposition(const Eigen::Matrix3d& s);

/// Kabsch / Umeyama: S = U Sigma V^T, R = V diag(1, 1, det(V U^T)) U^T. Always a proper rotation.
[[nodiscard]] Eigen::Matrix3d rotation_by_svd(const Eigen::Matrix3d& s);

enum class RotationSolver { kSvd, kPolarDenmanBeavers };

/// The chosen solver; the polar method falls back to the SVD when it fails or yields a reflection.
[[nodiscard]] Eigen::Matrix3d solve_rotation(const Eigen::Matrix3d& s, RotationSolver solver);

}  // namespace strata

#include "core/registration/rotation_solvers.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace strata {

Eigen::Matrix3d correlation_from_sums(const Eigen::Matrix3d& sum_dx, const Eigen::Vector3d& mean_d,
                                      const Eigen::Vector3d& mean_x, double count) {
  // sum (d - md)(x - mx)^T = sum d x^T - N md mx^T
  return sum_dx - count * mean_d * mean_x.transpose();
}

std::optional<Eigen::Matrix3d> polar_factor_denman_beavers(const Eigen::Matrix3d& m) {
  // The polar factor does not change under positive scaling; normalising keeps the iteration's inverses
  // well-conditioned whatever the number of pairs and the units.
  const double norm = m.norm();
  if (!(norm > 0.0) || !std::isfinite(norm))
    return std::nullopt;
  const Eigen::Matrix3d scaled = m / norm;
  Eigen::Matrix3d y = scaled.transpose() * scaled;  // Y0 = M^T M -> (M^T M)^(1/2)
  Eigen::Matrix3d z = Eigen::Matrix3d::Identity();  // Z0 = I     -> (M^T M)^(-1/2)
  constexpr int kMaxIterations = 60;
  constexpr double kSingular = 1e-12;
  for (int k = 0; k < kMaxIterations; ++k) {
    // A (near-)singular iterate means M^T M has a zero eigenvalue: the square root has no inverse.
    if (std::abs(y.determinant()) < kSingular || std::abs(z.determinant()) < kSingular)
      return std::nullopt;
    const Eigen::Matrix3d y_next = 0.5 * (y + z.inverse());
    const Eigen::Matrix3d z_next = 0.5 * (z + y.inverse());
    const double change = (y_next - y).norm();
    y = y_next;
    z = z_next;
    if (change < 1e-13 * y.norm()) {
      const Eigen::Matrix3d u = scaled * z;
      if (!u.allFinite() || !(u.transpose() * u).isApprox(Eigen::Matrix3d::Identity(), 1e-6))
        return std::nullopt;
      return u;
    }
  }
  return std::nullopt;
}

std::optional<Eigen::Matrix3d> rotation_by_polar_decomposition(const Eigen::Matrix3d& s) {
  std::optional<Eigen::Matrix3d> r = polar_factor_denman_beavers(s.transpose());
  if (!r || r->determinant() < 0.0)
    return std::nullopt;
  return r;
}

Eigen::Matrix3d rotation_by_svd(const Eigen::Matrix3d& s) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  correction(2, 2) = (v * u.transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return v * correction * u.transpose();
}

Eigen::Matrix3d solve_rotation(const Eigen::Matrix3d& s, RotationSolver solver) {
  if (solver == RotationSolver::kPolarDenmanBeavers) {
    if (const std::optional<Eigen::Matrix3d> r = rotation_by_polar_decomposition(s))
      return *r;
  }
  return rotation_by_svd(s);
}

}  // namespace strata

#include "core/registration/rotation_solvers.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace strata {
namespace {

/// S = sum d x^T over centred pairs with x = R d (+ noise): thesis eq. 4.5.
Eigen::Matrix3d correlation(const std::vector<Eigen::Vector3d>& data, const Eigen::Matrix3d& rotation,
                            double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  Eigen::Vector3d mean_d = Eigen::Vector3d::Zero(), mean_x = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> model;
  for (const Eigen::Vector3d& d : data) {
    model.push_back(rotation * d + Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
    mean_d += d;
    mean_x += model.back();
  }
  mean_d /= static_cast<double>(data.size());
  mean_x /= static_cast<double>(data.size());
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < data.size(); ++i)
    s += (data[i] - mean_d) * (model[i] - mean_x).transpose();
  return s;
}

std::vector<Eigen::Vector3d> spread_points(bool planar) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 200; ++i)
    points.emplace_back(u(rng), u(rng), planar ? 0.0 : u(rng));
  return points;
}

const Eigen::Matrix3d kRotation =
    Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();

TEST(RotationSolvers, PolarAndSvdAgreeOnGoodData) {
  const Eigen::Matrix3d s = correlation(spread_points(false), kRotation, 0.01, 1);
  const std::optional<Eigen::Matrix3d> polar = rotation_by_polar_decomposition(s);
  ASSERT_TRUE(polar.has_value());
  const Eigen::Matrix3d svd = rotation_by_svd(s);
  EXPECT_TRUE(polar->isApprox(svd, 1e-9));
  EXPECT_TRUE(svd.isApprox(kRotation, 1e-2));
  EXPECT_NEAR(svd.determinant(), 1.0, 1e-12);
}

TEST(RotationSolvers, LiteralPolarFactorOfSIsTheTranspose) {
  // The trap: eq. 4.6 applied to S itself (S formed data-then-model) yields R^T, not R.
  const Eigen::Matrix3d s = correlation(spread_points(false), kRotation, 0.0, 1);
  const std::optional<Eigen::Matrix3d> of_s = polar_factor_denman_beavers(s);
  ASSERT_TRUE(of_s.has_value());
  EXPECT_TRUE(of_s->isApprox(kRotation.transpose(), 1e-9));
  EXPECT_FALSE(of_s->isApprox(kRotation, 1e-3));
  EXPECT_TRUE(rotation_by_polar_decomposition(s)->isApprox(kRotation, 1e-9));
}

TEST(RotationSolvers, DenmanBeaversFindsTheInverseSquareRoot) {
  Eigen::Matrix3d m;
  m << 2, 0.3, 0.1, -0.2, 1.5, 0.4, 0.1, 0.2, 1.0;
  const std::optional<Eigen::Matrix3d> u = polar_factor_denman_beavers(m);
  ASSERT_TRUE(u.has_value());
  EXPECT_TRUE((u->transpose() * *u).isApprox(Eigen::Matrix3d::Identity(), 1e-10));
  // M = U P with P symmetric positive definite.
  const Eigen::Matrix3d p = u->transpose() * m;
  EXPECT_TRUE(p.isApprox(p.transpose(), 1e-9));
  EXPECT_GT(p.determinant(), 0.0);
}

TEST(RotationSolvers, ReflectionIsRejectedByPolarAndCorrectedBySvd) {
  // Mirrored pairs: the best orthonormal fit is a reflection (det -1). Polar returns it raw; the rotation
  // solvers must not.
  const std::vector<Eigen::Vector3d> data = spread_points(false);
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(2, 2) = -1.0;
  const Eigen::Matrix3d s = correlation(data, mirror, 0.0, 1);
  const std::optional<Eigen::Matrix3d> raw = polar_factor_denman_beavers(s.transpose());
  ASSERT_TRUE(raw.has_value());
  EXPECT_NEAR(raw->determinant(), -1.0, 1e-9);
  EXPECT_FALSE(rotation_by_polar_decomposition(s).has_value());
  EXPECT_NEAR(rotation_by_svd(s).determinant(), 1.0, 1e-12);
  EXPECT_NEAR(solve_rotation(s, RotationSolver::kPolarDenmanBeavers).determinant(), 1.0, 1e-12);
}

TEST(RotationSolvers, PlanarDataDefeatsPolarButNotSvd) {
  // All pairs in one plane: S has rank 2, S^T S is singular and has no inverse square root. The SVD with
  // the determinant guard still recovers the rotation.
  const Eigen::Matrix3d s = correlation(spread_points(true), kRotation, 0.0, 1);
  EXPECT_FALSE(rotation_by_polar_decomposition(s).has_value());
  EXPECT_TRUE(rotation_by_svd(s).isApprox(kRotation, 1e-9));
  EXPECT_TRUE(solve_rotation(s, RotationSolver::kPolarDenmanBeavers).isApprox(kRotation, 1e-9));
}

TEST(RotationSolvers, CorrelationFromSumsMatchesCentredSum) {
  const std::vector<Eigen::Vector3d> data = spread_points(false);
  Eigen::Matrix3d sum_dx = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean_d = Eigen::Vector3d::Zero(), mean_x = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& d : data) {
    sum_dx += d * (kRotation * d).transpose();
    mean_d += d;
    mean_x += kRotation * d;
  }
  const double n = static_cast<double>(data.size());
  const Eigen::Matrix3d s = correlation_from_sums(sum_dx, mean_d / n, mean_x / n, n);
  EXPECT_TRUE(s.isApprox(correlation(data, kRotation, 0.0, 1), 1e-9));
}

}  // namespace
}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "core/ann/growing_kdtree.hpp"
#include "core/points/point_cloud.hpp"
#include "core/registration/normals.hpp"
#include "core/registration/partner_search.hpp"
#include "core/registration/rotation_solvers.hpp"
#include "core/registration/surface_sides.hpp"

namespace strata {

/// What one ICP step minimises.
enum class IcpMetric {
  kPointToPoint,  ///< thesis eq. 4.2: sum |x_i - (R d_i + t)|^2, closed form per step
  kPointToPlane,  ///< sum (n_i . (x_i - (R d_i + t)))^2, one Gauss-Newton step per pairing
};

struct IcpOptions {
  /// Point-to-point (the thesis's metric) measured best over all the real pairs
  /// (tests/bench/registration_bench.cpp --variants); point-to-plane needs normals that the sparse lines of a
  /// pitching 2D scanner give poorly, and a fixed-scale kernel starves the coarse stages of pairs.
  IcpMetric metric = IcpMetric::kPointToPoint;
  RotationSolver rotation_solver = RotationSolver::kSvd;  ///< point-to-point only
  /// Pairs farther apart than this are no correspondence (the thesis's trimming, 0.25 m).
  double max_correspondence_distance = 0.25;
  /// Stop when the mean squared error changes by less than this between iterations (thesis tau), m^2.
  /// 0: never on the MSE.
  double mse_change_threshold = 1e-5;
  /// Stop when a step moves the source by less than both of these (metres, radians); 0: never on the step.
  /// Steadier than the MSE's change, which jumps as pairs come and go: the MSE stop let point-to-point ICP
  /// quit while it was still creeping by millimetres, at a point that depended on chance
  /// (tests/bench/registration_bench.cpp).
  double min_step_translation = 0.0;
  double min_step_rotation = 0.0;
  int max_iterations = 30;
  /// Geman-McClure kernel scale (m): pairs with residual r get weight (s^2 / (s^2 + r^2))^2. 0 = plain
  /// least squares over the trimmed pairs, as in the thesis.
  double kernel_scale = 0.0;
  /// Fewer pairs than this and a step is not taken (three pairs fix a pose; a few more guard the noise).
  std::size_t min_pairs = 6;
  /// Pairs across a thin wall (align's `sides`): they do not pull the pose across the wall. Point-to-plane
  /// keeps their turn, each wall's offset left free (its two faces are parallel); point-to-point drops
  /// them.
  SurfaceSideOptions surface_sides;
  /// Threads for each pairing's kd-tree searches and its target points' missing normals (point-to-plane),
  /// the caller's among them. The result is the same on any number: each search and each normal depends
  /// on its own point alone (docs/benchmarks.md, "The scan path on two threads").
  unsigned threads = 1;
};

struct IcpResult {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  ///< maps source points into the target frame
  std::vector<Correspondence> pairs;  ///< the final pairing, within the last correspondence bound
  double rmse = 0.0;                  ///< point-to-point distance over the final pairs, metres
  int iterations = 0;                 ///< pairing + update rounds, over all stages
  bool converged = false;             ///< the MSE or the steps settled before the iteration cap
};

/// ICP (thesis Algorithms 1 and 2): pair, solve for the transform, apply, until the MSE or the steps
/// settle.
/// `normals` serves the point-to-plane metric and may be null for point-to-point. `sides`, with normals,
/// tells the pairs across a thin wall (IcpOptions::surface_sides); the result's pairs are the others.
[[nodiscard]] IcpResult align(const PointCloud& source, const GrowingKdTree& target, LazyNormals* normals,
                              const Eigen::Isometry3d& guess, const IcpOptions& options,
                              const SurfaceSides* sides = nullptr);

}  // namespace strata

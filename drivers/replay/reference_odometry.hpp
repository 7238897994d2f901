#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/pose.hpp"

namespace strata::replay {

/// How much drift to add when odometry is made from reference poses: 1-sigma, per scan-to-scan step, growing
/// with the distance driven (as wheel slip does).
struct OdometryNoise {
  double translation = 0.0;  ///< metres of error per metre driven, along and across the motion
  double rotation = 0.0;     ///< radians of heading error per metre driven
  [[nodiscard]] bool none() const { return translation == 0.0 && rotation == 0.0; }
};

/// Planar wheel odometry along reference poses: each step between two reference poses, projected onto the
/// ground (x, y, heading), with seeded Gaussian noise added, integrated from the first reference pose. The
/// same poses, noise and seed give the same odometry. Without noise: the reference's planar part exactly.
[[nodiscard]] std::vector<Pose3> odometry_from_reference(const std::vector<Pose3>& reference,
                                                         const OdometryNoise& noise, std::uint64_t seed);

}  // namespace strata::replay

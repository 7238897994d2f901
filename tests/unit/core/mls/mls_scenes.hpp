#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <random>

#include "core/points/point_cloud.hpp"

namespace strata::test {

/// Points of the surface z = height(x, y) over [x0, x1] x [y0, y1], every `step`, with a little height
/// noise: how a scanner sees ground.
inline void add_surface(PointCloud& cloud, double x0, double x1, double y0, double y1,
                        const std::function<double(double, double)>& height, double step = 0.04,
                        double sigma = 0.003, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (double x = x0 + step / 2; x < x1; x += step)
    for (double y = y0 + step / 2; y < y1; y += step)
      cloud.emplace_back(x, y, height(x, y) + noise(rng));
}

inline void add_plane(PointCloud& cloud, double x0, double x1, double y0, double y1, double z,
                      double step = 0.04) {
  add_surface(
      cloud, x0, x1, y0, y1, [z](double, double) { return z; }, step);
}

/// A vertical face: the segment (x0, y0)-(x1, y1) extruded from z0 to z1.
inline void add_vertical_face(PointCloud& cloud, double x0, double y0, double x1, double y1, double z0,
                              double z1, double step = 0.04) {
  const double length = std::hypot(x1 - x0, y1 - y0);
  for (double s = step / 2; s < length; s += step)
    for (double z = z0 + step / 2; z < z1; z += step)
      cloud.emplace_back(x0 + (x1 - x0) * s / length, y0 + (y1 - y0) * s / length, z);
}

/// Whether the segment from `origin` to `end` passes through the axis-aligned box (slab test): for
/// scenes where something must hide what lies behind it.
inline bool segment_hits_box(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                             const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double t0 = 0.0;
  double t1 = 1.0;
  const Eigen::Vector3d d = end - origin;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-12) {
      if (origin[axis] < lo[axis] || origin[axis] > hi[axis])
        return false;
      continue;
    }
    double a = (lo[axis] - origin[axis]) / d[axis];
    double b = (hi[axis] - origin[axis]) / d[axis];
    if (a > b)
      std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1)
      return false;
  }
  return true;
}

}  // namespace strata::test

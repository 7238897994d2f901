#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <utility>

namespace strata::sim {

/// A ray p(t) = origin + t * direction, direction of unit length, t in metres.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;

  [[nodiscard]] Eigen::Vector3d at(double t) const { return origin + t * direction; }
};

/// An axis-aligned bounding box.
struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Aabb& other) {
    min = min.cwiseMin(other.min);
    max = max.cwiseMax(other.max);
  }
  [[nodiscard]] bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// The ray's parameter interval inside the box, clipped to [t_min, t_max]; empty when t0 > t1.
  [[nodiscard]] std::pair<double, double> clip(const Ray& ray, double t_min, double t_max) const {
    for (int axis = 0; axis < 3; ++axis) {
      if (ray.direction[axis] == 0.0) {
        if (ray.origin[axis] < min[axis] || ray.origin[axis] > max[axis])
          return {1.0, 0.0};
        continue;
      }
      const double inv = 1.0 / ray.direction[axis];
      double t0 = (min[axis] - ray.origin[axis]) * inv;
      double t1 = (max[axis] - ray.origin[axis]) * inv;
      if (t0 > t1)
        std::swap(t0, t1);
      t_min = std::max(t_min, t0);
      t_max = std::min(t_max, t1);
      if (t_min > t_max)
        return {1.0, 0.0};
    }
    return {t_min, t_max};
  }
};

}  // namespace strata::sim

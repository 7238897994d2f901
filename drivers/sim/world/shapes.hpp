#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "drivers/sim/world/ray.hpp"

namespace strata::sim {

/// A convex solid: the points p with n . p <= d for every bounding plane (n outward, unit length).
/// Boxes, ramps and stair steps are all convex solids, so one ray test serves them all.
class ConvexSolid {
 public:
  /// A box standing on its bottom face, rotated by `yaw` about the vertical through its centre.
  static ConvexSolid box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw);
  /// A wedge on the footprint (center_xy, length along yaw, width) from `base_z` up to a top that
  /// rises linearly from `height_start` (at the -length/2 end) to `height_end` (at the +length/2 end).
  static ConvexSolid ramp(const Eigen::Vector2d& center_xy, double length, double width, double yaw,
                          double base_z, double height_start, double height_end);

  [[nodiscard]] bool contains(const Eigen::Vector3d& p, double margin = 0.0) const;
  /// The entering distance of `ray` within [t_min, t_max], if it enters there. A ray that starts inside
  /// hits at t_min.
  [[nodiscard]] std::optional<double> intersect(const Ray& ray, double t_min, double t_max) const;
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }

 private:
  void add_plane(const Eigen::Vector3d& normal, const Eigen::Vector3d& point_on_plane);
  std::vector<Eigen::Vector4d> planes_;  // (n, d)
  Aabb bounds_;
};

/// An upright cylinder (tree trunk, pole, pillar).
struct Cylinder {
  Eigen::Vector2d center;
  double radius = 0.1;
  double z_min = 0.0;
  double z_max = 1.0;

  [[nodiscard]] bool contains(const Eigen::Vector3d& p, double margin = 0.0) const;
  [[nodiscard]] std::optional<double> intersect(const Ray& ray, double t_min, double t_max) const;
  [[nodiscard]] Aabb bounds() const;
};

/// A sphere (a tree's crown, a boulder).
struct Sphere {
  Eigen::Vector3d center;
  double radius = 1.0;

  [[nodiscard]] bool contains(const Eigen::Vector3d& p, double margin = 0.0) const;
  [[nodiscard]] std::optional<double> intersect(const Ray& ray, double t_min, double t_max) const;
  [[nodiscard]] Aabb bounds() const;
};

/// Terrain: heights on a regular grid of vertices, bilinear between them; solid below.
class HeightField {
 public:
  /// `heights` has ny rows of nx values; vertex (i, j) is at origin + (i, j) * cell.
  HeightField(Eigen::Vector2d origin, double cell, int nx, int ny, std::vector<double> heights);

  /// Height at (x, y), clamped to the grid's edge outside it.
  [[nodiscard]] double height(double x, double y) const;
  [[nodiscard]] std::optional<double> intersect(const Ray& ray, double t_min, double t_max) const;
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }
  [[nodiscard]] const Eigen::Vector2d& origin() const { return origin_; }
  [[nodiscard]] double cell() const { return cell_; }
  [[nodiscard]] int nx() const { return nx_; }
  [[nodiscard]] int ny() const { return ny_; }
  [[nodiscard]] const std::vector<double>& heights() const { return heights_; }

 private:
  [[nodiscard]] double vertex(int i, int j) const { return heights_[static_cast<std::size_t>(j * nx_ + i)]; }
  [[nodiscard]] std::optional<double> intersect_cell(const Ray& ray, int i, int j, double t0,
                                                     double t1) const;

  Eigen::Vector2d origin_;
  double cell_;
  int nx_;
  int ny_;
  std::vector<double> heights_;
  Aabb bounds_;
};

}  // namespace strata::sim

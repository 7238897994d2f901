#include "drivers/sim/world/shapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace strata::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The smallest root of a t^2 + b t + c in [lo, hi], if any.
std::optional<double> smallest_root(double a, double b, double c, double lo, double hi) {
  if (std::abs(a) < 1e-12) {
    if (std::abs(b) < 1e-15)
      return std::nullopt;
    const double t = -c / b;
    return (t >= lo && t <= hi) ? std::optional(t) : std::nullopt;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0)
    return std::nullopt;
  // Numerically stable form: avoids cancellation when b^2 >> 4ac.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a;
  double t1 = (q != 0.0) ? c / q : t0;
  if (t0 > t1)
    std::swap(t0, t1);
  if (t0 >= lo && t0 <= hi)
    return t0;
  if (t1 >= lo && t1 <= hi)
    return t1;
  return std::nullopt;
}

}  // namespace

// --- ConvexSolid -------------------------------------------------------------------------------

void ConvexSolid::add_plane(const Eigen::Vector3d& normal, const Eigen::Vector3d& point_on_plane) {
  const Eigen::Vector3d n = normal.normalized();
  planes_.emplace_back(n.x(), n.y(), n.z(), n.dot(point_on_plane));
}

ConvexSolid ConvexSolid::box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw) {
  if ((size.array() <= 0.0).any())
    throw std::invalid_argument("box size must be positive");
  ConvexSolid solid;
  const Eigen::Vector3d ux(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d uy(-std::sin(yaw), std::cos(yaw), 0.0);
  const Eigen::Vector3d uz = Eigen::Vector3d::UnitZ();
  const std::array<Eigen::Vector3d, 3> axes{ux, uy, uz};
  for (int k = 0; k < 3; ++k) {
    solid.add_plane(axes[k], center + axes[k] * size[k] / 2);
    solid.add_plane(-axes[k], center - axes[k] * size[k] / 2);
  }
  for (int corner = 0; corner < 8; ++corner) {
    const double sx = (corner & 1) ? 0.5 : -0.5;
    const double sy = (corner & 2) ? 0.5 : -0.5;
    const double sz = (corner & 4) ? 0.5 : -0.5;
    solid.bounds_.extend(center + ux * sx * size.x() + uy * sy * size.y() + uz * sz * size.z());
  }
  return solid;
}

ConvexSolid ConvexSolid::ramp(const Eigen::Vector2d& center_xy, double length, double width, double yaw,
                              double base_z, double height_start, double height_end) {
  if (length <= 0.0 || width <= 0.0)
    throw std::invalid_argument("ramp length and width must be positive");
  if (height_start < base_z || height_end < base_z || std::max(height_start, height_end) <= base_z) {
    throw std::invalid_argument("ramp heights must be above its base");
  }
  ConvexSolid solid;
  const Eigen::Vector3d c(center_xy.x(), center_xy.y(), base_z);
  const Eigen::Vector3d ux(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d uy(-std::sin(yaw), std::cos(yaw), 0.0);
  solid.add_plane(-Eigen::Vector3d::UnitZ(), c);
  solid.add_plane(ux, c + ux * length / 2);
  solid.add_plane(-ux, c - ux * length / 2);
  solid.add_plane(uy, c + uy * width / 2);
  solid.add_plane(-uy, c - uy * width / 2);
  // Top: z = height_start + slope * (u + length / 2), u along ux.
  const double slope = (height_end - height_start) / length;
  const Eigen::Vector3d top_normal = Eigen::Vector3d::UnitZ() - slope * ux;
  solid.add_plane(top_normal, Eigen::Vector3d(c.x(), c.y(), 0.0) - ux * length / 2 +
                                  Eigen::Vector3d(0.0, 0.0, height_start));
  for (int corner = 0; corner < 4; ++corner) {
    const double su = (corner & 1) ? 0.5 : -0.5;
    const double sv = (corner & 2) ? 0.5 : -0.5;
    const Eigen::Vector3d foot = c + ux * su * length + uy * sv * width;
    solid.bounds_.extend(foot);
    solid.bounds_.extend(Eigen::Vector3d(foot.x(), foot.y(), su < 0 ? height_start : height_end));
  }
  return solid;
}

bool ConvexSolid::contains(const Eigen::Vector3d& p, double margin) const {
  return std::all_of(planes_.begin(), planes_.end(), [&](const Eigen::Vector4d& plane) {
    return plane.head<3>().dot(p) - plane.w() < -margin;
  });
}

std::optional<double> ConvexSolid::intersect(const Ray& ray, double t_min, double t_max) const {
  double t_enter = t_min;
  double t_exit = t_max;
  for (const Eigen::Vector4d& plane : planes_) {
    const double denom = plane.head<3>().dot(ray.direction);
    const double inside = plane.w() - plane.head<3>().dot(ray.origin);  // > 0 on the inner side
    if (denom == 0.0) {
      if (inside < 0.0)
        return std::nullopt;  // parallel and outside this face
      continue;
    }
    const double t = inside / denom;
    if (denom < 0.0) {
      t_enter = std::max(t_enter, t);
    } else {
      t_exit = std::min(t_exit, t);
    }
    if (t_enter > t_exit)
      return std::nullopt;
  }
  return t_enter;
}

// --- Cylinder ----------------------------------------------------------------------------------

bool Cylinder::contains(const Eigen::Vector3d& p, double margin) const {
  const double r = radius - margin;
  return p.z() > z_min + margin && p.z() < z_max - margin && (p.head<2>() - center).squaredNorm() < r * r;
}

std::optional<double> Cylinder::intersect(const Ray& ray, double t_min, double t_max) const {
  // The slab between the caps.
  if (ray.direction.z() != 0.0) {
    double t0 = (z_min - ray.origin.z()) / ray.direction.z();
    double t1 = (z_max - ray.origin.z()) / ray.direction.z();
    if (t0 > t1)
      std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
  } else if (ray.origin.z() < z_min || ray.origin.z() > z_max) {
    return std::nullopt;
  }
  if (t_min > t_max)
    return std::nullopt;
  // The infinite cylinder's side.
  const Eigen::Vector2d o = ray.origin.head<2>() - center;
  const Eigen::Vector2d d = ray.direction.head<2>();
  const double a = d.squaredNorm();
  const double c = o.squaredNorm() - radius * radius;
  if (a < 1e-18) {  // vertical ray: inside the circle or never
    return c <= 0.0 ? std::optional(t_min) : std::nullopt;
  }
  const double b = 2.0 * o.dot(d);
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0)
    return std::nullopt;
  const double root = std::sqrt(disc);
  const double s0 = (-b - root) / (2.0 * a);
  const double s1 = (-b + root) / (2.0 * a);
  const double enter = std::max(t_min, s0);
  const double exit = std::min(t_max, s1);
  if (enter > exit)
    return std::nullopt;
  return enter;
}

Aabb Cylinder::bounds() const {
  return {Eigen::Vector3d(center.x() - radius, center.y() - radius, z_min),
          Eigen::Vector3d(center.x() + radius, center.y() + radius, z_max)};
}

// --- Sphere ------------------------------------------------------------------------------------

bool Sphere::contains(const Eigen::Vector3d& p, double margin) const {
  const double r = radius - margin;
  return (p - center).squaredNorm() < r * r;
}

std::optional<double> Sphere::intersect(const Ray& ray, double t_min, double t_max) const {
  const Eigen::Vector3d o = ray.origin - center;
  const double b = o.dot(ray.direction);
  const double c = o.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0)
    return std::nullopt;
  const double root = std::sqrt(disc);
  const double enter = std::max(t_min, -b - root);
  const double exit = std::min(t_max, -b + root);
  if (enter > exit)
    return std::nullopt;
  return enter;
}

Aabb Sphere::bounds() const {
  return {center - Eigen::Vector3d::Constant(radius), center + Eigen::Vector3d::Constant(radius)};
}

// --- HeightField -------------------------------------------------------------------------------

HeightField::HeightField(Eigen::Vector2d origin, double cell, int nx, int ny, std::vector<double> heights)
    : origin_(std::move(origin)), cell_(cell), nx_(nx), ny_(ny), heights_(std::move(heights)) {
  if (!(cell_ > 0.0) || nx_ < 2 || ny_ < 2)
    throw std::invalid_argument("height field needs cell > 0 and 2x2 vertices");
  if (heights_.size() != static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_)) {
    throw std::invalid_argument("height field needs nx * ny heights");
  }
  if (!std::all_of(heights_.begin(), heights_.end(), [](double h) { return std::isfinite(h); })) {
    throw std::invalid_argument("height field heights must be finite");
  }
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  bounds_.min = {origin_.x(), origin_.y(), *lo};
  bounds_.max = {origin_.x() + (nx_ - 1) * cell_, origin_.y() + (ny_ - 1) * cell_, *hi};
}

double HeightField::height(double x, double y) const {
  const double gx = std::clamp((x - origin_.x()) / cell_, 0.0, static_cast<double>(nx_ - 1));
  const double gy = std::clamp((y - origin_.y()) / cell_, 0.0, static_cast<double>(ny_ - 1));
  const int i = std::min(static_cast<int>(gx), nx_ - 2);
  const int j = std::min(static_cast<int>(gy), ny_ - 2);
  const double u = gx - i;
  const double v = gy - j;
  return vertex(i, j) * (1 - u) * (1 - v) + vertex(i + 1, j) * u * (1 - v) + vertex(i, j + 1) * (1 - u) * v +
         vertex(i + 1, j + 1) * u * v;
}

std::optional<double> HeightField::intersect_cell(const Ray& ray, int i, int j, double t0, double t1) const {
  const double h00 = vertex(i, j);
  const double h10 = vertex(i + 1, j);
  const double h01 = vertex(i, j + 1);
  const double h11 = vertex(i + 1, j + 1);
  const Eigen::Vector3d p = ray.at(t0);
  // Skip cells the segment passes wholly above: the common case for rays far over the terrain.
  const double z_low = std::min(p.z(), p.z() + ray.direction.z() * (t1 - t0));
  if (z_low > std::max({h00, h10, h01, h11}))
    return std::nullopt;
  // In cell units the surface is bilinear, h = A + B u + C v + D u v, so along the ray
  // f(s) = z(s) - h(u(s), v(s)) is quadratic in s = t - t0.
  const double u0 = (p.x() - origin_.x()) / cell_ - i;
  const double v0 = (p.y() - origin_.y()) / cell_ - j;
  const double du = ray.direction.x() / cell_;
  const double dv = ray.direction.y() / cell_;
  const double A = h00, B = h10 - h00, C = h01 - h00, D = h00 - h10 - h01 + h11;
  const double a2 = -D * du * dv;
  const double a1 = ray.direction.z() - B * du - C * dv - D * (u0 * dv + v0 * du);
  const double a0 = p.z() - A - B * u0 - C * v0 - D * u0 * v0;
  if (a0 <= 0.0)
    return t0;  // the segment starts under the surface
  const auto s = smallest_root(a2, a1, a0, 0.0, t1 - t0);
  if (!s)
    return std::nullopt;
  return t0 + *s;
}

std::optional<double> HeightField::intersect(const Ray& ray, double t_min, double t_max) const {
  auto [t, t_end] = bounds_.clip(ray, t_min, t_max);
  if (t > t_end)
    return std::nullopt;
  // 2D DDA over the cells the ray crosses (Amanatides and Woo).
  const Eigen::Vector3d start = ray.at(t);
  int i = std::clamp(static_cast<int>(std::floor((start.x() - origin_.x()) / cell_)), 0, nx_ - 2);
  int j = std::clamp(static_cast<int>(std::floor((start.y() - origin_.y()) / cell_)), 0, ny_ - 2);
  const double dx = ray.direction.x();
  const double dy = ray.direction.y();
  const int step_i = dx > 0 ? 1 : -1;
  const int step_j = dy > 0 ? 1 : -1;
  const double next_x = origin_.x() + (i + (dx > 0 ? 1 : 0)) * cell_;
  const double next_y = origin_.y() + (j + (dy > 0 ? 1 : 0)) * cell_;
  double t_next_x = dx != 0.0 ? (next_x - ray.origin.x()) / dx : kInf;
  double t_next_y = dy != 0.0 ? (next_y - ray.origin.y()) / dy : kInf;
  const double t_delta_x = dx != 0.0 ? cell_ / std::abs(dx) : kInf;
  const double t_delta_y = dy != 0.0 ? cell_ / std::abs(dy) : kInf;
  while (t <= t_end) {
    const double t_cell_end = std::min({t_next_x, t_next_y, t_end});
    if (auto hit = intersect_cell(ray, i, j, t, t_cell_end))
      return hit;
    if (t_next_x < t_next_y) {
      i += step_i;
      t = t_next_x;
      t_next_x += t_delta_x;
    } else {
      j += step_j;
      t = t_next_y;
      t_next_y += t_delta_y;
    }
    if (i < 0 || j < 0 || i > nx_ - 2 || j > ny_ - 2 || t_cell_end >= t_end)
      break;
  }
  return std::nullopt;
}

}  // namespace strata::sim

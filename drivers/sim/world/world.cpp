#include "drivers/sim/world/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace strata::sim {
namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}

World::World(WorldDescription description, double grid_cell)
    : description_(std::move(description)), cell_(grid_cell) {
  for (const BoxShape& box : description_.boxes)
    solids_.push_back(ConvexSolid::box(box.center, box.size, box.yaw));
  for (const RampShape& ramp : description_.ramps) {
    solids_.push_back(ConvexSolid::ramp(ramp.center, ramp.length, ramp.width, ramp.yaw, ramp.base_z,
                                        ramp.height_start, ramp.height_end));
  }
  for (const auto& solid : solids_)
    bounds_.extend(solid.bounds());
  for (const auto& cylinder : description_.cylinders)
    bounds_.extend(cylinder.bounds());
  for (const auto& sphere : description_.spheres)
    bounds_.extend(sphere.bounds());
  if (description_.terrain)
    bounds_.extend(description_.terrain->bounds());
  if (!(bounds_.min.array() <= bounds_.max.array()).all())
    throw std::invalid_argument("the world is empty");

  nx_ = std::max(1, static_cast<int>(std::ceil((bounds_.max.x() - bounds_.min.x()) / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((bounds_.max.y() - bounds_.min.y()) / cell_)));
  grid_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  for (unsigned i = 0; i < solids_.size(); ++i)
    add_to_grid({Kind::kSolid, i}, solids_[i].bounds());
  for (unsigned i = 0; i < description_.cylinders.size(); ++i) {
    add_to_grid({Kind::kCylinder, i}, description_.cylinders[i].bounds());
  }
  for (unsigned i = 0; i < description_.spheres.size(); ++i) {
    add_to_grid({Kind::kSphere, i}, description_.spheres[i].bounds());
  }
}

int World::cell_x(double x) const {
  return std::clamp(static_cast<int>(std::floor((x - bounds_.min.x()) / cell_)), 0, nx_ - 1);
}
int World::cell_y(double y) const {
  return std::clamp(static_cast<int>(std::floor((y - bounds_.min.y()) / cell_)), 0, ny_ - 1);
}

void World::add_to_grid(Ref ref, const Aabb& box) {
  for (int j = cell_y(box.min.y()); j <= cell_y(box.max.y()); ++j) {
    for (int i = cell_x(box.min.x()); i <= cell_x(box.max.x()); ++i) {
      grid_[static_cast<std::size_t>(j * nx_ + i)].push_back(ref);
    }
  }
}

std::optional<double> World::intersect(Ref ref, const Ray& ray, double t_min, double t_max) const {
  switch (ref.kind) {
    case Kind::kSolid:
      return solids_[ref.index].intersect(ray, t_min, t_max);
    case Kind::kCylinder:
      return description_.cylinders[ref.index].intersect(ray, t_min, t_max);
    case Kind::kSphere:
      return description_.spheres[ref.index].intersect(ray, t_min, t_max);
  }
  return std::nullopt;
}

bool World::contains(Ref ref, const Eigen::Vector3d& p, double margin) const {
  switch (ref.kind) {
    case Kind::kSolid:
      return solids_[ref.index].contains(p, margin);
    case Kind::kCylinder:
      return description_.cylinders[ref.index].contains(p, margin);
    case Kind::kSphere:
      return description_.spheres[ref.index].contains(p, margin);
  }
  return false;
}

std::optional<RayHit> World::cast(const Ray& ray, double max_range) const {
  double best = max_range;
  bool hit = false;
  auto [t, t_end] = bounds_.clip(ray, 0.0, max_range);
  if (t <= t_end) {
    // 2D DDA over the grid; stop once the nearest hit lies within the cells already visited.
    const Eigen::Vector3d start = ray.at(t);
    int i = cell_x(start.x());
    int j = cell_y(start.y());
    const double dx = ray.direction.x();
    const double dy = ray.direction.y();
    const int step_i = dx > 0 ? 1 : -1;
    const int step_j = dy > 0 ? 1 : -1;
    double t_next_x =
        dx != 0.0 ? (bounds_.min.x() + (i + (dx > 0 ? 1 : 0)) * cell_ - ray.origin.x()) / dx : kInfinity;
    double t_next_y =
        dy != 0.0 ? (bounds_.min.y() + (j + (dy > 0 ? 1 : 0)) * cell_ - ray.origin.y()) / dy : kInfinity;
    const double t_delta_x = dx != 0.0 ? cell_ / std::abs(dx) : kInfinity;
    const double t_delta_y = dy != 0.0 ? cell_ / std::abs(dy) : kInfinity;
    while (true) {
      for (const Ref& ref : grid_[static_cast<std::size_t>(j * nx_ + i)]) {
        if (auto t_hit = intersect(ref, ray, 0.0, best)) {
          best = *t_hit;
          hit = true;
        }
      }
      const double t_cell_end = std::min(t_next_x, t_next_y);
      if (best <= t_cell_end || t_cell_end >= t_end)
        break;
      if (t_next_x < t_next_y) {
        i += step_i;
        t_next_x += t_delta_x;
      } else {
        j += step_j;
        t_next_y += t_delta_y;
      }
      if (i < 0 || j < 0 || i >= nx_ || j >= ny_)
        break;
    }
  }
  if (description_.terrain) {
    if (auto t_hit = description_.terrain->intersect(ray, 0.0, best)) {
      best = *t_hit;
      hit = true;
    }
  }
  if (!hit)
    return std::nullopt;
  return RayHit{best, ray.at(best)};
}

bool World::inside_solid(const Eigen::Vector3d& p, double margin) const {
  if (description_.terrain) {
    const Aabb& tb = description_.terrain->bounds();
    if (p.x() >= tb.min.x() && p.x() <= tb.max.x() && p.y() >= tb.min.y() && p.y() <= tb.max.y() &&
        p.z() < description_.terrain->height(p.x(), p.y()) - margin) {
      return true;
    }
  }
  if (!bounds_.contains(p))
    return false;
  const auto& cell = grid_[static_cast<std::size_t>(cell_y(p.y()) * nx_ + cell_x(p.x()))];
  return std::any_of(cell.begin(), cell.end(), [&](const Ref& ref) { return contains(ref, p, margin); });
}

std::optional<double> World::surface_below(double x, double y, double z_from) const {
  const Ray down{{x, y, z_from}, -Eigen::Vector3d::UnitZ()};
  const auto hit = cast(down, z_from - bounds_.min.z() + 1.0);
  if (!hit)
    return std::nullopt;
  return hit->point.z();
}

}  // namespace strata::sim

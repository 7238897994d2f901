#include "drivers/sim/world.hpp"

#include <algorithm>
#include <utility>

namespace strata::sim {

World::World(double half_extent, std::vector<Box> boxes)
    : half_extent_(half_extent), boxes_(std::move(boxes)) {}

World World::yard() {
  const double h = 10.0;      // half extent of the yard
  const double wall = 0.2;    // fence thickness
  const double height = 1.0;  // fence height
  std::vector<Box> boxes = {
      {"fence-north", {-h, h - wall, 0.0}, {h, h, height}},
      {"fence-south", {-h, -h, 0.0}, {h, -h + wall, height}},
      {"fence-east", {h - wall, -h, 0.0}, {h, h, height}},
      {"fence-west", {-h, -h, 0.0}, {-h + wall, h, height}},
      {"crate", {-1.0, -1.0, 0.0}, {1.0, 1.0, 1.2}},
      {"pallet", {5.5, 4.5, 0.0}, {7.0, 6.5, 0.4}},
      {"cabinet", {-7.0, 3.0, 0.0}, {-6.2, 5.0, 1.9}},
      {"column", {4.0, -6.5, 0.0}, {4.6, -5.9, 2.5}},
  };
  return World(h, std::move(boxes));
}

double World::ground_height(double /*x*/, double /*y*/) const {
  return 0.0;
}

bool World::collides(double x, double y, double radius, double height) const {
  const double ground = ground_height(x, y);
  return std::any_of(boxes_.begin(), boxes_.end(), [&](const Box& box) {
    if (box.min.z() >= ground + height || box.max.z() <= ground)
      return false;
    const double nearest_x = std::clamp(x, box.min.x(), box.max.x());
    const double nearest_y = std::clamp(y, box.min.y(), box.max.y());
    const double dx = x - nearest_x;
    const double dy = y - nearest_y;
    return dx * dx + dy * dy < radius * radius;
  });
}

}  // namespace strata::sim

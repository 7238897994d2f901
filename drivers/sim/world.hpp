#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace strata::sim {

/// An axis-aligned box standing on the ground (or floating, when min.z() > 0).
struct Box {
  std::string name;
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

/// The simulated world: flat ground bounded by a square fence of boxes. Later worlds add ramps,
/// height fields, stairs and bridges; the interface (what is solid where) stays.
class World {
 public:
  World(double half_extent, std::vector<Box> boxes);

  /// The first-cut world: a 20 m x 20 m yard with a fence and a few boxes around a driving loop.
  [[nodiscard]] static World yard();

  [[nodiscard]] double half_extent() const { return half_extent_; }
  [[nodiscard]] const std::vector<Box>& boxes() const { return boxes_; }
  /// Ground height at (x, y). Flat for now.
  [[nodiscard]] double ground_height(double x, double y) const;
  /// Whether a vertical cylinder of `radius` standing at (x, y) on the ground touches any box that
  /// reaches below `height` above the ground.
  [[nodiscard]] bool collides(double x, double y, double radius, double height) const;

 private:
  double half_extent_;
  std::vector<Box> boxes_;
};

}  // namespace strata::sim

#pragma once

#include <array>
#include <string>

#include "core/geometry/pose.hpp"
#include "drivers/sim/world/world.hpp"

namespace strata::sim {

/// The shape and climbing ability of the robot's base: a wheelchair by default (thesis: "Alfred").
struct BaseGeometry {
  double wheelbase = 0.8;      ///< m between front and rear wheel contacts
  double track = 0.6;          ///< m between left and right wheel contacts
  double length = 1.05;        ///< m, body footprint
  double width = 0.66;         ///< m, body footprint
  double height = 1.3;         ///< m, body top above the ground (the scanner is below it)
  double clearance = 0.1;      ///< m, body underside above the ground
  double max_step = 0.06;      ///< m a wheel can climb or drop at once (a curb is higher)
  double max_slope_deg = 9.0;  ///< steepest tilt the base accepts, roll or pitch
};

/// Where the base stands: its full pose on the terrain and the height under each wheel.
struct Stance {
  Pose3 pose;                      ///< z: ground height under the base's centre; roll, pitch from the wheels
  std::array<double, 4> wheels{};  ///< ground under front-left, front-right, rear-left, rear-right
};

/// Puts a planar pose onto the terrain, or says why the base cannot be there: the physics that lets
/// the robot tilt on a ramp and keeps it from climbing stairs or driving through walls.
class TerrainPlacer {
 public:
  TerrainPlacer(const World& world, BaseGeometry geometry);

  /// The stance at `spawn`, on the first surface below `z_hint` + a step (multi-level worlds).
  [[nodiscard]] Stance spawn(const Pose2& spawn, double z_hint) const;

  struct Result {
    bool ok = false;
    Stance stance;
    std::string blocked_by;  ///< why not, when !ok: "step", "slope", "obstacle", "no ground"
  };
  /// Moving from `from` to the planar pose `to` (one short simulation step).
  [[nodiscard]] Result move(const Stance& from, const Pose2& to) const;

  [[nodiscard]] const BaseGeometry& geometry() const { return geometry_; }

 private:
  [[nodiscard]] std::array<Eigen::Vector2d, 4> wheel_positions(const Pose2& pose) const;
  [[nodiscard]] Stance stance_from_wheels(const Pose2& planar, const std::array<double, 4>& wheels) const;
  [[nodiscard]] bool body_collides(const Stance& stance) const;

  const World& world_;
  BaseGeometry geometry_;
  double max_slope_;
};

}  // namespace strata::sim

#include "drivers/sim/terrain_base.hpp"

#include <cmath>
#include <stdexcept>

#include "core/geometry/angles.hpp"

namespace strata::sim {

TerrainPlacer::TerrainPlacer(const World& world, BaseGeometry geometry)
    : world_(world), geometry_(geometry), max_slope_(geometry.max_slope_deg * kPi / 180.0) {}

std::array<Eigen::Vector2d, 4> TerrainPlacer::wheel_positions(const Pose2& pose) const {
  const Eigen::Vector2d forward(std::cos(pose.theta), std::sin(pose.theta));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  const Eigen::Vector2d c(pose.x, pose.y);
  const Eigen::Vector2d f = forward * geometry_.wheelbase / 2;
  const Eigen::Vector2d l = left * geometry_.track / 2;
  return {c + f + l, c + f - l, c - f + l, c - f - l};
}

Stance TerrainPlacer::stance_from_wheels(const Pose2& planar, const std::array<double, 4>& w) const {
  Stance stance;
  stance.wheels = w;
  const double front = (w[0] + w[1]) / 2;
  const double rear = (w[2] + w[3]) / 2;
  const double left = (w[0] + w[2]) / 2;
  const double right = (w[1] + w[3]) / 2;
  stance.pose.position = {planar.x, planar.y, (front + rear) / 2};
  stance.pose.yaw = planar.theta;
  // Nose up is a negative pitch about y (R = Rz Ry Rx, x forward): the front wheels sit higher.
  stance.pose.pitch = -std::atan2(front - rear, geometry_.wheelbase);
  stance.pose.roll = std::atan2(left - right, geometry_.track);
  return stance;
}

bool TerrainPlacer::body_collides(const Stance& stance) const {
  // Sample the body's volume: a grid over the footprint at a few heights above the clearance,
  // carried by the tilted base.
  const Eigen::Isometry3d base = stance.pose.to_isometry();
  const double margin = 0.01;  // touching a surface is not a collision
  for (int iz = 0; iz < 3; ++iz) {
    const double z = geometry_.clearance + (geometry_.height - geometry_.clearance) * iz / 2.0;
    for (int ix = 0; ix < 5; ++ix) {
      for (int iy = 0; iy < 3; ++iy) {
        const Eigen::Vector3d local(geometry_.length * (ix / 4.0 - 0.5), geometry_.width * (iy / 2.0 - 0.5),
                                    z);
        if (world_.inside_solid(base * local, margin))
          return true;
      }
    }
  }
  return false;
}

Stance TerrainPlacer::spawn(const Pose2& spawn, double z_hint) const {
  std::array<double, 4> wheels{};
  const auto positions = wheel_positions(spawn);
  for (int k = 0; k < 4; ++k) {
    const auto ground = world_.surface_below(positions[k].x(), positions[k].y(), z_hint + 0.5);
    if (!ground)
      throw std::runtime_error("the robot's spawn point has no ground under it");
    wheels[k] = *ground;
  }
  return stance_from_wheels(spawn, wheels);
}

TerrainPlacer::Result TerrainPlacer::move(const Stance& from, const Pose2& to) const {
  Result result;
  const auto old_positions = wheel_positions({from.pose.position.x(), from.pose.position.y(), from.pose.yaw});
  const auto new_positions = wheel_positions(to);
  std::array<double, 4> wheels{};
  for (int k = 0; k < 4; ++k) {
    // A wheel may rise by a step plus what the steepest drivable slope gives over the distance moved;
    // probing from just above that, any higher surface reads as a step too high.
    const double moved = (new_positions[k] - old_positions[k]).norm();
    const double max_rise = geometry_.max_step + moved * std::tan(max_slope_);
    const auto ground =
        world_.surface_below(new_positions[k].x(), new_positions[k].y(), from.wheels[k] + max_rise + 0.005);
    if (!ground) {
      result.blocked_by = "no ground";
      return result;
    }
    const double change = *ground - from.wheels[k];
    if (change > max_rise || change < -max_rise) {  // a kerb or a stair, up or down
      result.blocked_by = "step";
      return result;
    }
    wheels[k] = *ground;
  }
  result.stance = stance_from_wheels(to, wheels);
  if (std::abs(result.stance.pose.pitch) > max_slope_ || std::abs(result.stance.pose.roll) > max_slope_) {
    result.blocked_by = "slope";
    return result;
  }
  if (body_collides(result.stance)) {
    result.blocked_by = "obstacle";
    return result;
  }
  result.ok = true;
  return result;
}

}  // namespace strata::sim

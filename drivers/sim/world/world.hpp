#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "drivers/sim/world/ray.hpp"
#include "drivers/sim/world/shapes.hpp"

namespace strata::sim {

/// A box, as written in a world file (stairs are expanded into boxes).
struct BoxShape {
  std::string name;
  Eigen::Vector3d center;
  Eigen::Vector3d size;
  double yaw = 0.0;
};

/// A ramp (a wedge whose top slopes along its length), as written in a world file.
struct RampShape {
  std::string name;
  Eigen::Vector2d center;
  double length = 1.0;
  double width = 1.0;
  double yaw = 0.0;
  double base_z = 0.0;
  double height_start = 0.0;  ///< absolute top height at the -length/2 end
  double height_end = 0.0;    ///< absolute top height at the +length/2 end
};

/// Everything a world file says: the geometry, where the robot starts and the route it drives.
struct WorldDescription {
  std::string name;
  std::string summary;
  std::vector<BoxShape> boxes;
  std::vector<RampShape> ramps;
  std::vector<Cylinder> cylinders;
  std::vector<Sphere> spheres;
  std::optional<HeightField> terrain;
  Pose2 spawn;
  double spawn_z = 0.0;                ///< a height near the floor the robot starts on (multi-level worlds)
  std::vector<Eigen::Vector2d> route;  ///< the demo loop the robot drives, in order
};

/// The first surface a ray meets.
struct RayHit {
  double distance = 0.0;
  Eigen::Vector3d point;
};

/// The simulated world: solid geometry that rays hit and the robot stands on. Immutable once built;
/// queries are const and thread-safe. A uniform grid over the ground plane lists the shapes that overlap
/// each cell, so a ray only tests what lies along its path.
class World {
 public:
  explicit World(WorldDescription description, double grid_cell = 2.0);

  /// The first surface along `ray` within `max_range`.
  [[nodiscard]] std::optional<RayHit> cast(const Ray& ray, double max_range) const;
  /// Whether `p` lies inside solid geometry (deeper than `margin`).
  [[nodiscard]] bool inside_solid(const Eigen::Vector3d& p, double margin = 0.0) const;
  /// Height of the first surface straight below (x, y, z_from); nothing when there is no ground.
  [[nodiscard]] std::optional<double> surface_below(double x, double y, double z_from) const;

  [[nodiscard]] const WorldDescription& description() const { return description_; }
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }

 private:
  enum class Kind : unsigned char { kSolid, kCylinder, kSphere };
  struct Ref {
    Kind kind;
    unsigned index;
  };
  void add_to_grid(Ref ref, const Aabb& box);
  [[nodiscard]] std::optional<double> intersect(Ref ref, const Ray& ray, double t_min, double t_max) const;
  [[nodiscard]] bool contains(Ref ref, const Eigen::Vector3d& p, double margin) const;
  [[nodiscard]] int cell_x(double x) const;
  [[nodiscard]] int cell_y(double y) const;

  WorldDescription description_;
  std::vector<ConvexSolid> solids_;  // boxes then ramps
  Aabb bounds_;
  double cell_;
  int nx_ = 0;
  int ny_ = 0;
  std::vector<std::vector<Ref>> grid_;
};

}  // namespace strata::sim

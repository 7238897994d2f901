#pragma once

#include <Eigen/Core>
#include <cmath>

#include "core/mls/mls_map.hpp"
#include "core/points/point_cloud.hpp"
#include "drivers/sim/world/world.hpp"

namespace strata::test {

/// An MLS map of a simulator world as complete scans would build it, without the cost of simulating
/// them: for every cell of [x0, x1] x [y0, y1] the top of every solid (a horizontal surface, the points a
/// scanner sees from above) and the sides of solids that face open air (vertical surfaces: walls, the
/// edges of ramps and steps). Deterministic and quick, for tests that need a map of a large world.
inline MlsMap survey_world(const sim::World& world, double x0, double y0, double x1, double y1,
                           double resolution = 0.2) {
  MlsConfig config;
  config.resolution = resolution;
  config.free_space_ray_stride = 0;  // points, not rays: nothing to clear
  MlsMap map(config);
  const double top = world.bounds().max.z() + 1.0;
  const double floor = world.bounds().min.z() - 1.0;
  const auto& terrain = world.description().terrain;
  const double side = 0.55 * resolution;
  constexpr double kStep = 0.04;
  PointCloud points;
  for (double x = (std::floor(x0 / resolution) + 0.5) * resolution; x < x1; x += resolution)
    for (double y = (std::floor(y0 / resolution) + 0.5) * resolution; y < y1; y += resolution) {
      double from = top;
      while (const auto surface = world.surface_below(x, y, from)) {
        points.emplace_back(x, y, *surface);
        // Walk down through the solid; where open air lies beside it, a scanner sees its side.
        double z = *surface - kStep;
        const double ground = terrain ? terrain->height(x, y) : floor;
        for (; z > floor && world.inside_solid({x, y, z}); z -= kStep) {
          if (z < ground)
            break;  // the terrain: solid all the way down
          if (!world.inside_solid({x + side, y, z}) || !world.inside_solid({x - side, y, z}) ||
              !world.inside_solid({x, y + side, z}) || !world.inside_solid({x, y - side, z}))
            points.emplace_back(x, y, z);
        }
        if (z < ground || z <= floor)
          break;
        from = z - 1e-3;
      }
    }
  const Eigen::Vector3d origin((x0 + x1) / 2, (y0 + y1) / 2, top);
  map.insert_scan(points, origin);
  return map;
}

}  // namespace strata::test

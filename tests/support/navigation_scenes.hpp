#pragma once

#include <memory>

#include "core/mls/mls_map.hpp"
#include "core/navigation/patch_graph.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata::test {

/// Hand-made scenes are point sets without occlusion: free-space clearing stays off.
inline MlsConfig scene_config(double resolution = 0.1) {
  MlsConfig config;
  config.resolution = resolution;
  config.free_space_ray_stride = 0;
  return config;
}

/// A road (ground at z = 0, x in [-10, 10], y in [-6, 24]) under a deck at z = 1.5 (x in [-1.5, 1.5],
/// y in [-5, 5]) whose north end continues as a 1:10 ramp down to the road at y = 20. The deck's south
/// end and its sides are drops; the ramp has walls on both sides.
inline MlsMap bridge_scene() {
  MlsMap map(scene_config());
  constexpr double kSpacing = 0.07;  // every 0.1 m cell gets a point; fewer points keep sanitizer runs short
  PointCloud points;
  add_plane(points, -10, -1.5, -6, 24, 0.0, kSpacing);
  add_plane(points, 1.5, 10, -6, 24, 0.0, kSpacing);
  add_plane(points, -1.5, 1.5, -6, 5, 0.0, kSpacing);  // the road under the deck
  add_plane(points, -1.5, 1.5, 20, 24, 0.0, kSpacing);
  add_surface(
      points, -1.5, 1.5, 5, 20, [](double, double y) { return 1.5 * (20.0 - y) / 15.0; }, kSpacing);
  add_vertical_face(points, -1.52, 5, -1.52, 20, 0.0, 1.5, kSpacing);
  add_vertical_face(points, 1.52, 5, 1.52, 20, 0.0, 1.5, kSpacing);
  map.insert_scan(points, {0, 10, 8});
  PointCloud deck;
  add_plane(deck, -1.5, 1.5, -5, 5, 1.5, kSpacing);
  map.insert_scan(deck, {0, 10, 8});
  return map;
}

/// Flat ground (z = 0, x and y in [-5, 5]) with a wall along x = -3 from y = -5 to y = 5 and, from x = 2
/// east, three stairs of 0.15 m rise and 0.3 m run up to a landing at 0.45 m.
inline MlsMap wall_and_stairs_scene() {
  MlsMap map(scene_config());
  PointCloud points;
  add_plane(points, -5, 2, -5, 5, 0.0);
  for (int step = 0; step < 3; ++step) {
    const double x = 2.0 + 0.3 * step;
    const double z = 0.15 * (step + 1);
    add_vertical_face(points, x + 0.01, -5, x + 0.01, 5, z - 0.15, z);
    add_plane(points, x, x + 0.3, -5, 5, z);
  }
  add_plane(points, 2.9, 5, -5, 5, 0.45);
  add_vertical_face(points, -3.0, -5, -3.0, 5, 0.0, 2.0);
  map.insert_scan(points, {0, 0, 3});
  return map;
}

inline std::shared_ptr<const SurfaceGrid> surfaces_of(const MlsMap& map,
                                                      const TraversabilityConfig& config = {}) {
  return std::make_shared<const SurfaceGrid>(map, CellRegion::of_tiles(map.tile_indices()), config);
}

inline PatchGraph graph_of(const MlsMap& map, const PatchGraphConfig& config = {}) {
  return PatchGraph(surfaces_of(map, config.traversability), map.resolution(), config);
}

}  // namespace strata::test

#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/points/point_cloud.hpp"
#include "core/registration/normals.hpp"
#include "core/registration/partner_search.hpp"

namespace strata {

/// Where the sensor was that saw each target point, and where the source's sensor is. A thin wall's two
/// faces lie closer than ICP's correspondence bound: a scan that sees one face pairs with the other face
/// the map holds, seen from the other side, and is pulled by the wall's thickness (the campus lab's wall
/// at its door: 7 cm across the hallway, docs/benchmarks.md "Thin walls").
struct SurfaceSides {
  const std::vector<Eigen::Vector3d>* target_viewpoints = nullptr;  ///< per target point, target frame
  Eigen::Vector3d source_viewpoint = Eigen::Vector3d::Zero();       ///< source frame
};

struct SurfaceSideOptions {
  bool enabled = true;
  /// A side is taken for sure beyond `margin` plus `normal_error` (radians) times the range from the
  /// surface: near its plane, the estimated normal's error can put a viewpoint on either side.
  double normal_error = 0.03;
  double margin = 0.05;  ///< metres
};

/// A pair across a thin wall, and the surface its target lies on (the target's normal turned towards the
/// source's sensor in 15-degree bins, and the plane's offset in 1 m bins): one wall's pairs share it.
struct AcrossPair {
  Correspondence pair;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< the target's, turned towards the source's sensor
  std::uint64_t surface = 0;
};

/// Moves the pairs whose target was seen from the other side of its surface than the source's sensor
/// (both sides sure) from `pairs` to `across`. `source_to_target`: the current estimate.
void split_across(const Eigen::Isometry3d& source_to_target, const PointCloud& target, LazyNormals& normals,
                  const SurfaceSides& sides, const SurfaceSideOptions& options,
                  std::vector<Correspondence>& pairs, std::vector<AcrossPair>& across);

}  // namespace strata

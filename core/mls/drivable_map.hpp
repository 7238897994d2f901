#pragma once

#include <Eigen/Core>

#include "core/mls/level_grid.hpp"
#include "core/mls/mls_map.hpp"
#include "core/mls/traversability.hpp"

namespace strata {

struct DrivableMap {
  LevelGrid grid;
  bool start_found = false;  ///< the robot's cell has a horizontal patch near its ground height
  std::size_t free_cells = 0;
};

/// The occupancy at the robot's level (docs/architecture.md 4.3): a flood fill from the patch under
/// `robot_ground` (the map-frame point the robot stands on) across links between traversable patches of
/// 4-neighbouring cells whose heights differ by at most max_step, within `region`. Reached -> free; a cell
/// with patches that the fill does not reach (a wall, a step, the deck above when the robot is on the road)
/// -> occupied; a cell without patches -> unknown. Because the fill follows patches, not cells, a bridge
/// overhead does not block the road and a ramp stays connected.
[[nodiscard]] DrivableMap compute_drivable_map(const MlsMap& map, const TraversabilityConfig& config,
                                               const Eigen::Vector3d& robot_ground, const CellRegion& region);

/// The same over `surfaces`' region, classified already: for a caller that uses the classification for
/// more than the fill (the mapping worker marks traversable patches in the tiles it streams).
[[nodiscard]] DrivableMap compute_drivable_map(const MlsMap& map, const SurfaceGrid& surfaces,
                                               const TraversabilityConfig& config,
                                               const Eigen::Vector3d& robot_ground);

/// The region of the tiles changed since `version` joined with the tiles around the robot: what a new scan
/// asks to recompute.
[[nodiscard]] CellRegion changed_region(const MlsMap& map, std::uint64_t version,
                                        const Eigen::Vector3d& robot_ground);

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/mls/level_grid.hpp"
#include "core/mls/mls_map.hpp"
#include "core/mls/traversability.hpp"

namespace strata {

struct DrivableMap {
  LevelGrid grid;
  bool start_found = false;  ///< the robot's cell has a horizontal patch near its ground height
  /// Per cell: 1 where the fill from the robot reached (connected to it by drivable ground, measured or
  /// inferred), 0 elsewhere; free cells it did not reach are drivable ground not known to connect.
  std::vector<std::uint8_t> connected;
  std::size_t free_cells = 0;
  std::size_t connected_cells = 0;
};

/// The occupancy at the robot's level (docs/architecture.md 4.3): a flood fill from the patch under
/// `robot_ground` (the map-frame point the robot stands on) across links between traversable patches of
/// 4-neighbouring cells whose heights differ by at most max_step, within `region`, over the measured
/// surfaces and those inferred across the gaps a scanner leaves between its rings (unseen_gaps.hpp), as the
/// planner sees them. Reached -> free (and `connected`). The cells the fill does not reach are judged
/// against the level of the nearest reached ground: occupied where something stops the robot (a wall, a
/// steep slope, ground under a low ceiling, ground higher or lower than the level could climb to over the
/// distance: a step, a landing, a drop); free where there is drivable ground the level could reach (a
/// ring of floor too far out to be joined, floor behind a wall: whether a way leads there is the
/// planner's question); unknown where only something overhead was seen (the deck, from the road) or
/// nothing. Because the fill follows patches, not cells, a bridge overhead does not block the road and a
/// ramp stays connected.
[[nodiscard]] DrivableMap compute_drivable_map(const MlsMap& map, const TraversabilityConfig& config,
                                               const Eigen::Vector3d& robot_ground, const CellRegion& region);

/// The same over `surfaces`' region, classified already (measured surfaces; the gaps are inferred here):
/// for a caller that uses the classification for more than the fill (the mapping worker marks traversable
/// patches in the tiles it streams).
[[nodiscard]] DrivableMap compute_drivable_map(const MlsMap& map, const SurfaceGrid& surfaces,
                                               const TraversabilityConfig& config,
                                               const Eigen::Vector3d& robot_ground);

/// The region of the tiles changed since `version` joined with the tiles around the robot: what a new scan
/// asks to recompute.
[[nodiscard]] CellRegion changed_region(const MlsMap& map, std::uint64_t version,
                                        const Eigen::Vector3d& robot_ground);

}  // namespace strata

#pragma once

#include "core/mls/traversability.hpp"

namespace strata {

struct UnseenGapConfig {
  /// Longest unseen stretch bridged, metres; 0 bridges none. A tilting laser's slices meet flat ground in
  /// rings about d^2 * step / h apart (1 degree steps from 1.05 m up: 0.4 m at 5 m, 1.4 m at 9 m); a
  /// spinning lidar's rings spread the same way.
  double max_gap = 1.5;
  /// Steepest grade assumed across a gap, rise per metre, on top of the max_step any two cells may differ.
  /// Kept below ramps' grades on purpose: a steep unseen stretch may as well be a drop.
  double max_grade = 0.1;
};

/// Inferred drivable surfaces where a scanner left gaps (docs/architecture.md 4.4): along each of the four
/// grid lines through a measured drivable surface, an unseen stretch of up to max_gap that ends on another
/// drivable surface at a compatible height gets surfaces at the interpolated heights. Why that is sound
/// for open ground: the ray that found the far surface passed low over the stretch (its height above the
/// ground shrinks to zero at its end) and would have hit anything standing there. Only stretches with
/// nothing at or below the height of the line are filled, so a wall, a step or a drop (its lower ground
/// seen) ends a line, while the road under a bridge deck is filled under the deck. Lines across a shadow
/// behind an obstacle are filled too: that is optimistic, as planners usually are about unknown space, and
/// the next scans correct it before the robot gets there.
[[nodiscard]] SurfaceGrid fill_unseen_gaps(const SurfaceGrid& grid, double resolution,
                                           const TraversabilityConfig& traversability,
                                           const UnseenGapConfig& config);

}  // namespace strata

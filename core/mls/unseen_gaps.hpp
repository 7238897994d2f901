#pragma once

#include "core/mls/traversability.hpp"

namespace strata {

/// Inferred drivable surfaces where a scanner left gaps (docs/architecture.md 4.4): along each of the four
/// grid lines through a measured drivable surface, an unseen stretch of up to max_gap that ends on another
/// drivable surface at a compatible height gets surfaces at the interpolated heights. Why that is sound
/// for open ground: the ray that found the far surface passed low over the stretch (its height above the
/// ground shrinks to zero at its end) and would have hit anything standing there. Only stretches with
/// nothing at or below the height of the line are filled, so a wall, a step or a drop (its lower ground
/// seen) ends a line, while the road under a bridge deck is filled under the deck. But ground seen far
/// below a narrow stretch was seen from the side (UnseenGapConfig::overhang_depth), and a stretch the
/// wheels span is no drop whatever lies below (max_slot): the deck over the road is filled too. Lines across
/// a shadow behind an obstacle are filled too: that is optimistic, as planners usually are about unknown
/// space, and the next scans correct it before the robot gets there. `traversability.unseen_gaps` sets how
/// far; a max_gap of 0 returns the grid as it is.
[[nodiscard]] SurfaceGrid fill_unseen_gaps(const SurfaceGrid& grid, double resolution,
                                           const TraversabilityConfig& traversability);

}  // namespace strata

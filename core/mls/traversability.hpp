#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/mls/mls_map.hpp"

namespace strata {

struct UnseenGapConfig {
  /// Longest unseen stretch bridged, metres; 0 bridges none. A tilting laser's slices meet flat ground in
  /// rings about d^2 * step / h apart (1 degree steps from 1.05 m up: 0.4 m at 5 m, 1.4 m at 9 m); a
  /// spinning lidar's rings spread the same way.
  double max_gap = 1.5;
  /// Steepest grade assumed across a gap, rise per metre, on top of the max_step any two cells may differ.
  /// Kept below ramps' grades on purpose: a steep unseen stretch may as well be a drop.
  double max_grade = 0.1;
  /// Ground seen at least overhang_depth below a gap at most max_overhang_gap wide, or a face reaching down
  /// that deep (its top hidden by the gap), ends no line: no scanner saw it through the gap (from h above the
  /// gap, ground D below shows through a gap w wide only within w * h / D of it: 0.4 m for a scanner 2 m up),
  /// but from the side, under what the gap lies in. Bands of a bridge deck no scan saw from above, the road
  /// under them seen from beside the bridge, closed the deck (issue 58); a hole the robot could fall into
  /// shows its floor only from its edge.
  double overhang_depth = 2.0;
  double max_overhang_gap = 0.4;  ///< metres
  /// A stretch this narrow is bridged whatever was seen lower down in it, metres: the wheels span it. The
  /// lidar demo's deck held single cells where only its underside was seen, 0.25-0.3 m below the deck,
  /// and the robot's clearance kept it off the deck around them (issue 58). Diagonal lines (0.14 m a
  /// cell) bridge none.
  double max_slot = 0.1;
};

/// What the robot can drive on (docs/architecture.md 4.3). Defaults: the thesis's wheelchair.
struct TraversabilityConfig {
  double max_step = 0.08;  ///< highest step between neighbouring cells, metres
  /// A height difference the two patches' own uncertainty explains is no step: up to this many of their
  /// combined standard deviations beyond max_step (issue 58: a lidar's far cells, seen once from 20-30 m,
  /// sigma 0.1-0.15 m, stood 0.08-0.1 m from their neighbours as steps, and their edges left the robot no
  /// room on flat ground). Closer scans shrink a patch's sigma, and a real step is a step again.
  double step_sigmas = 1.0;
  /// The most uncertainty forgives on top of max_step, metres: a far, noisy view never hides a curb
  /// higher than the two together. 0.12 rather than 0.08: a ring of the campus ramp seen from the deck
  /// 12 m away lay 0.12-0.25 m below the ramp across its width, and the robot could not cross it to a
  /// goal below (issue 58); near, the cells are sure and the step is max_step again.
  double max_uncertain_step = 0.12;
  double max_slope = 0.2618;  ///< steepest ground, radians (15 degrees)
  double robot_height = 1.0;  ///< free space needed above a patch to drive there, metres
  /// The robot's patch is the horizontal patch nearest its ground height within this, metres.
  double start_tolerance = 0.5;
  /// If the robot's own cell has no such patch (scanners rarely see the ground under the robot), the
  /// nearest cell within this radius that has one, metres.
  double start_search_radius = 1.0;
  /// Gaps the scanner left in drivable ground, bridged by inferred surfaces (core/mls/unseen_gaps.hpp) for
  /// the drivable map and the planner alike.
  UnseenGapConfig unseen_gaps;
};

/// A rectangle of cells in global cell indices.
struct CellRegion {
  CellIndex min;
  int width = 0;
  int height = 0;

  [[nodiscard]] bool contains(CellIndex cell) const {
    return cell.x >= min.x && cell.y >= min.y && cell.x < min.x + width && cell.y < min.y + height;
  }
  /// The smallest region holding both.
  [[nodiscard]] static CellRegion bounding(const CellRegion& a, const CellRegion& b);
  /// The cells of the given tiles' bounding box.
  [[nodiscard]] static CellRegion of_tiles(const std::vector<TileIndex>& tiles);
};

/// The patches of a region flattened into arrays (one hash lookup per tile, then plain indexing), each
/// classified as traversable or not: horizontal, clearance to the patch above at least robot_height, and
/// the local slope, from the patches two cells away on each axis, at most max_slope; or driven over.
class SurfaceGrid {
 public:
  struct Surface {
    float top = 0.0F;
    float bottom = 0.0F;
    /// Of `top`, m^2 (MlsPatch::variance): how far apart two surfaces may measure and still meet.
    float variance = 0.0F;
    bool vertical = false;
    bool traversable = false;
    /// Not measured: inferred where the scanner left a gap (core/mls/unseen_gaps.hpp).
    bool inferred = false;
    /// The robot stood on it (MlsPatch::kDriven): traversable whatever the slope estimate or the patch above
    /// say, so the robot never strands itself on a map that misreads the ground it is on.
    bool driven = false;
    /// The robot's centre passed over it (MlsPatch::kTrack): it fitted there (PatchGraph::passable).
    bool track = false;
  };

  SurfaceGrid(const MlsMap& map, const CellRegion& region, const TraversabilityConfig& config);

  /// A copy with more surfaces, each (cell index, surface) already classified, kept lowest first per cell;
  /// seams the new surfaces continue become traversable.
  [[nodiscard]] SurfaceGrid with_added(std::vector<std::pair<std::size_t, Surface>> added) const;

  /// The one rule for moving from cell to cell, shared by the drivable map's fill, the patch graph's edges
  /// and the seams: the traversable surface of local cell (col, row) that a surface at height `top` (of
  /// that variance) steps onto, the nearest in height and within the step the two surfaces may differ by
  /// (step_limit; ties to the higher one). None outside the region.
  [[nodiscard]] std::optional<std::uint32_t> step_onto(int col, int row, float top, float variance) const;
  /// The largest height difference between two surfaces of these variances that is no step: max_step, and
  /// up to step_sigmas of their combined standard deviation more, at most max_uncertain_step more.
  [[nodiscard]] float step_limit(float variance_a, float variance_b) const;

  /// Which surfaces may hold the robot or a goal.
  enum class Standing {
    kTraversable,  ///< what the robot may drive on: the planner's start and goal
    kHorizontal,   ///< any horizontal surface: where the robot stands, whatever the classification says
  };
  /// The one rule for placing the robot or a goal: the surface of local cell (col, row) nearest the height
  /// z within `tolerance` (ties to the higher one) or, when that cell has none, the nearest such surface in
  /// the nearest ring of cells around it within `rings` that has one (scanners rarely see the ground under
  /// the robot). None when no cell within the rings has one.
  [[nodiscard]] std::optional<std::uint32_t> nearest_surface(int col, int row, double z, double tolerance,
                                                             int rings, Standing standing) const;
  /// Local (col, row) of a global cell; it may lie outside the region.
  [[nodiscard]] std::pair<int, int> local(CellIndex cell) const {
    return {cell.x - region_.min.x, cell.y - region_.min.y};
  }
  [[nodiscard]] bool contains_local(int col, int row) const {
    return col >= 0 && row >= 0 && col < region_.width && row < region_.height;
  }

  [[nodiscard]] const CellRegion& region() const { return region_; }
  /// Index of the cell at local (col, row).
  [[nodiscard]] std::size_t cell(int col, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(region_.width) +
           static_cast<std::size_t>(col);
  }
  /// Surfaces of a cell, lowest first; indices into all_surfaces() from first_surface(cell).
  [[nodiscard]] std::span<const Surface> surfaces(std::size_t cell) const {
    return {surfaces_.data() + begin_[cell], surfaces_.data() + begin_[cell + 1]};
  }
  [[nodiscard]] std::uint32_t first_surface(std::size_t cell) const { return begin_[cell]; }
  [[nodiscard]] std::size_t surface_count() const { return surfaces_.size(); }
  /// A surface by its index (first_surface(cell) + i).
  [[nodiscard]] const Surface& surface(std::uint32_t index) const { return surfaces_[index]; }
  /// The index of the cell that holds surface `index`.
  [[nodiscard]] std::size_t cell_of_surface(std::uint32_t index) const;

 private:
  /// The horizontal surface in (col, row) whose top is nearest `height` (within 0.5 m), if any; with
  /// `slabs`, any surface.
  [[nodiscard]] const Surface* neighbour(int col, int row, float height, bool slabs = false) const;
  void classify();
  /// Where one structure ends against another (a ramp's end under a bridge deck), the cell at the seam
  /// holds the end face seen from below and the surface seen from above: one vertical patch. Its top is
  /// traversable when traversable surfaces continue it within a step on opposite sides, with room above.
  void drive_over_seams();

  CellRegion region_;
  double cell_size_;
  TraversabilityConfig config_;
  std::vector<std::uint32_t> begin_;  ///< per cell, then one past the end
  std::vector<Surface> surfaces_;
  /// Per cell: its one horizontal surface's height; NaN if empty; infinity if anything else. Only for
  /// classify(); empty in a copy made by with_added().
  std::vector<float> simple_height_;
};

}  // namespace strata

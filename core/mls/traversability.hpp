#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/mls/mls_map.hpp"

namespace strata {

/// What the robot can drive on (docs/architecture.md 4.3). Defaults: the thesis's wheelchair.
struct TraversabilityConfig {
  double max_step = 0.08;     ///< highest step between neighbouring cells, metres
  double max_slope = 0.2618;  ///< steepest ground, radians (15 degrees)
  double robot_height = 1.0;  ///< free space needed above a patch to drive there, metres
  /// The robot's patch is the horizontal patch nearest its ground height within this, metres.
  double start_tolerance = 0.5;
  /// If the robot's own cell has no such patch (scanners rarely see the ground under the robot), the
  /// nearest cell within this radius that has one, metres.
  double start_search_radius = 1.0;
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
/// the local slope, from the patches two cells away on each axis, at most max_slope.
class SurfaceGrid {
 public:
  struct Surface {
    float top = 0.0F;
    float bottom = 0.0F;
    bool vertical = false;
    bool traversable = false;
    /// Not measured: inferred where the scanner left a gap (core/navigation/unseen_gaps.hpp).
    bool inferred = false;
  };

  SurfaceGrid(const MlsMap& map, const CellRegion& region, const TraversabilityConfig& config);

  /// A copy with more surfaces, each (cell index, surface) already classified, kept lowest first per cell.
  [[nodiscard]] SurfaceGrid with_added(std::vector<std::pair<std::size_t, Surface>> added) const;

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

 private:
  /// Height of the horizontal surface in (col, row) nearest `height` (within 0.5 m), if any.
  [[nodiscard]] bool neighbour_height(int col, int row, float height, float& out) const;
  void classify(const TraversabilityConfig& config);

  CellRegion region_;
  double cell_size_;
  std::vector<std::uint32_t> begin_;  ///< per cell, then one past the end
  std::vector<Surface> surfaces_;
  /// Per cell: its one horizontal surface's height; NaN if empty; infinity if anything else. Only for
  /// classify(); empty in a copy made by with_added().
  std::vector<float> simple_height_;
};

}  // namespace strata

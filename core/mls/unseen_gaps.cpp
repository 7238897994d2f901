#include "core/mls/unseen_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace strata {
namespace {

/// Half of the eight grid directions: each line is walked from its lower end only.
constexpr int kLineDirections[4][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}};

}  // namespace

SurfaceGrid fill_unseen_gaps(const SurfaceGrid& grid, double resolution,
                             const TraversabilityConfig& traversability) {
  const UnseenGapConfig& config = traversability.unseen_gaps;
  const int max_cells = static_cast<int>(std::floor(config.max_gap / resolution + 1e-9));
  if (max_cells < 1)
    return grid;
  const CellRegion& region = grid.region();
  const auto robot_height = static_cast<float>(traversability.robot_height);
  const auto overhang_depth = static_cast<float>(config.overhang_depth);
  const double max_overhang_gap = config.max_overhang_gap;
  const double max_slot = config.max_slot;
  const auto max_step = static_cast<float>(traversability.max_step);
  // A slab's top counts as measured ground: classify() keeps a vertical patch traversable only where
  // level ground continues its top on every side (a deck seen from below and above). Not an anchor, the
  // deck's slab cells ended every line across it and left its unseen cells holes (issue 58).
  const auto measured_drivable = [](const SurfaceGrid::Surface& s) { return s.traversable && !s.inferred; };
  std::vector<std::pair<std::size_t, SurfaceGrid::Surface>> added;
  for (int row = 0; row < region.height; ++row)
    for (int col = 0; col < region.width; ++col)
      for (const SurfaceGrid::Surface& from : grid.surfaces(grid.cell(col, row))) {
        if (!measured_drivable(from))
          continue;
        for (const auto& direction : kLineDirections) {
          const int dx = direction[0];
          const int dy = direction[1];
          const double cell_length = resolution * ((dx != 0 && dy != 0) ? std::sqrt(2.0) : 1.0);
          // How wide the stretch may be, given what was seen below it so far (max_slot, max_overhang_gap).
          double widest = std::numeric_limits<double>::infinity();
          for (int k = 1; k <= max_cells + 1; ++k) {
            const int c = col + k * dx;
            const int r = row + k * dy;
            if (c < 0 || r < 0 || c >= region.width || r >= region.height)
              break;
            const auto climb = static_cast<float>(k * cell_length * config.max_grade);
            const SurfaceGrid::Surface* end = nullptr;
            bool blocked = false;
            for (const SurfaceGrid::Surface& s : grid.surfaces(grid.cell(c, r))) {
              if (measured_drivable(s) &&
                  std::abs(s.top - from.top) <= grid.step_limit(from.variance, s.variance) + climb &&
                  (end == nullptr || std::abs(s.top - from.top) < std::abs(end->top - from.top)))
                end = &s;
              // Anything at the line's height or below it ends the line: a wall, a step, or ground seen
              // lower down (a drop; and a surface above ground that rays reached cannot be there). Ground
              // seen lower down under a stretch the wheels span does not (max_slot), nor anything reaching so
              // deep under one so narrow that it was seen from the side (overhang_depth): ground, or a face
              // rising from there whose top the stretch hid (the bridge deck's seam with the plateau, seen
              // from the road up to 0.4 m below the deck, closed the deck in the lidar demo: issue 58).
              if (s.bottom > from.top + robot_height)
                continue;
              if (s.top > from.top - max_step)
                blocked = true;
              else
                widest =
                    std::min(widest, s.bottom <= from.top - overhang_depth ? max_overhang_gap : max_slot);
            }
            if (end != nullptr) {
              for (int i = 1; i < k; ++i) {
                const float top =
                    from.top + (end->top - from.top) * static_cast<float>(i) / static_cast<float>(k);
                added.push_back({grid.cell(col + i * dx, row + i * dy),
                                 {.top = top,
                                  .bottom = top,
                                  .variance = std::max(from.variance, end->variance),  // known no better
                                  .vertical = false,
                                  .traversable = true,
                                  .inferred = true}});
              }
              break;
            }
            if (blocked || k * cell_length > widest + 1e-6)
              break;
          }
        }
      }
  // Lines crossing in a gap infer a surface each: one per cell and level is enough.
  std::sort(added.begin(), added.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second.top < b.second.top;
  });
  std::vector<std::pair<std::size_t, SurfaceGrid::Surface>> kept;
  kept.reserve(added.size());
  for (const auto& item : added)
    if (kept.empty() || kept.back().first != item.first ||
        item.second.top - kept.back().second.top > max_step)
      kept.push_back(item);
  return grid.with_added(std::move(kept));
}

}  // namespace strata

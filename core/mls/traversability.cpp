#include "core/mls/traversability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata {
namespace {

/// A height's weight in the slope's plane is kSureVariance / (kSureVariance + its variance), its inverse
/// variance scaled to at most 1: 1/2 for sigma 1 cm (a near lidar cell), 1/160 for 0.125 m (a far one).
/// The floor stands for what no patch's variance holds (a cell's own roughness).
constexpr double kSureVariance = 0.01 * 0.01;
/// Beyond a step and a slope, a neighbour still joins the plane as far as the two heights' uncertainty
/// reaches past this much each (8.5 cm together): a far ring's 0.12-0.22 m does. At 3 cm, the landing
/// beside the campus stairs (a survey from above) took the stairs' first step into its plane and lost the
/// room the robot stops in (CampusNavigation.GoalsInAWallOrOnTheStairs...); 4-8 cm keep both.
constexpr double kSureReach = 0.06 * 0.06;

}  // namespace

CellRegion CellRegion::bounding(const CellRegion& a, const CellRegion& b) {
  if (a.width <= 0 || a.height <= 0)
    return b;
  if (b.width <= 0 || b.height <= 0)
    return a;
  const int min_x = std::min(a.min.x, b.min.x);
  const int min_y = std::min(a.min.y, b.min.y);
  const int max_x = std::max(a.min.x + a.width, b.min.x + b.width);
  const int max_y = std::max(a.min.y + a.height, b.min.y + b.height);
  return {{min_x, min_y}, max_x - min_x, max_y - min_y};
}

CellRegion CellRegion::of_tiles(const std::vector<TileIndex>& tiles) {
  CellRegion region;
  for (const TileIndex& tile : tiles)
    region = bounding(region, {{tile.x * kMlsTileSize, tile.y * kMlsTileSize}, kMlsTileSize, kMlsTileSize});
  return region;
}

SurfaceGrid::SurfaceGrid(const MlsMap& map, const CellRegion& region, const TraversabilityConfig& config)
    : region_(region), cell_size_(map.resolution()), config_(config) {
  const std::size_t cells = static_cast<std::size_t>(std::max(region.width, 0)) *
                            static_cast<std::size_t>(std::max(region.height, 0));
  begin_.reserve(cells + 1);
  surfaces_.reserve(cells + cells / 4);
  for (int row = 0; row < region.height; ++row) {
    const MlsTile* tile = nullptr;
    int tile_x = std::numeric_limits<int>::min();
    for (int col = 0; col < region.width; ++col) {
      const CellIndex index{region.min.x + col, region.min.y + row};
      const TileIndex tile_index = MlsMap::tile_of(index);
      if (tile_index.x != tile_x) {  // one lookup per tile a row crosses
        tile_x = tile_index.x;
        tile = map.find_tile(tile_index);
      }
      begin_.push_back(static_cast<std::uint32_t>(surfaces_.size()));
      if (tile != nullptr)
        tile->for_each_patch(MlsMap::local_index(index), [&](const MlsPatch& patch) {
          surfaces_.push_back({.top = patch.top(),
                               .bottom = patch.bottom(),
                               .variance = patch.variance,
                               .vertical = patch.vertical(),
                               .driven = patch.driven(),
                               .track = patch.on_track()});
        });
    }
  }
  begin_.push_back(static_cast<std::uint32_t>(surfaces_.size()));
  // Most cells hold one horizontal patch: keep its height in a flat array so the slope estimate (eight
  // neighbour lookups per patch) reads one float instead of walking a cell's surfaces.
  simple_height_.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    const std::uint32_t count = begin_[c + 1] - begin_[c];
    if (count == 0)
      simple_height_[c] = std::numeric_limits<float>::quiet_NaN();
    else if (count == 1 && !surfaces_[begin_[c]].vertical)
      simple_height_[c] = surfaces_[begin_[c]].top;
    else
      simple_height_[c] = std::numeric_limits<float>::infinity();
  }
  classify();
  drive_over_seams();
}

const SurfaceGrid::Surface* SurfaceGrid::neighbour(int col, int row, float height, bool slabs) const {
  if (col < 0 || row < 0 || col >= region_.width || row >= region_.height)
    return nullptr;
  const std::size_t c = cell(col, row);
  const float simple = simple_height_[c];
  if (std::isnan(simple))
    return nullptr;
  if (std::isfinite(simple))
    return std::abs(simple - height) < 0.5F ? &surfaces_[begin_[c]] : nullptr;
  float best = 0.5F;
  const Surface* found = nullptr;
  for (const Surface& s : surfaces(c)) {
    if (s.vertical && !slabs)
      continue;
    const float difference = std::abs(s.top - height);
    if (difference < best) {
      best = difference;
      found = &s;
    }
  }
  return found;
}

SurfaceGrid SurfaceGrid::with_added(std::vector<std::pair<std::size_t, Surface>> added) const {
  if (added.empty())
    return *this;
  std::stable_sort(added.begin(), added.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  SurfaceGrid copy = *this;
  copy.simple_height_.clear();
  copy.surfaces_.clear();
  copy.surfaces_.reserve(surfaces_.size() + added.size());
  auto next = added.begin();
  const std::size_t cells = begin_.size() - 1;
  for (std::size_t c = 0; c < cells; ++c) {
    copy.begin_[c] = static_cast<std::uint32_t>(copy.surfaces_.size());
    copy.surfaces_.insert(copy.surfaces_.end(), surfaces_.begin() + begin_[c],
                          surfaces_.begin() + begin_[c + 1]);
    if (next == added.end() || next->first != c)
      continue;
    for (; next != added.end() && next->first == c; ++next)
      copy.surfaces_.push_back(next->second);
    std::stable_sort(copy.surfaces_.begin() + copy.begin_[c], copy.surfaces_.end(),
                     [](const Surface& a, const Surface& b) { return a.top < b.top; });
  }
  copy.begin_[cells] = static_cast<std::uint32_t>(copy.surfaces_.size());
  copy.drive_over_seams();
  return copy;
}

std::size_t SurfaceGrid::cell_of_surface(std::uint32_t index) const {
  // begin_ never decreases: the cell is the last one whose first surface is at or before `index`.
  return static_cast<std::size_t>(std::upper_bound(begin_.begin(), begin_.end(), index) - begin_.begin()) - 1;
}

float SurfaceGrid::step_limit(float variance_a, float variance_b) const {
  const double forgiven = config_.step_sigmas * std::sqrt(static_cast<double>(variance_a + variance_b));
  return static_cast<float>(config_.max_step + std::min(forgiven, config_.max_uncertain_step));
}

std::optional<std::uint32_t> SurfaceGrid::step_onto(int col, int row, float top, float variance) const {
  if (!contains_local(col, row))
    return std::nullopt;
  const std::size_t c = cell(col, row);
  std::optional<std::uint32_t> best;
  float best_difference = std::numeric_limits<float>::infinity();
  const auto max_step = static_cast<float>(config_.max_step);
  for (std::uint32_t i = begin_[c]; i < begin_[c + 1]; ++i) {
    const float difference = std::abs(surfaces_[i].top - top);
    // Within max_step is a step whatever the variances (most neighbours): the square root only beyond.
    if (surfaces_[i].traversable && difference <= best_difference &&
        (difference <= max_step || difference <= step_limit(variance, surfaces_[i].variance))) {
      best_difference = difference;
      best = i;
    }
  }
  return best;
}

std::optional<std::uint32_t> SurfaceGrid::nearest_surface(int centre_col, int centre_row, double z,
                                                          double tolerance, int rings,
                                                          Standing standing) const {
  if (!std::isfinite(z))
    return std::nullopt;
  for (int ring = 0; ring <= rings; ++ring) {
    std::optional<std::uint32_t> best;
    double best_difference = tolerance;
    for (int dy = -ring; dy <= ring; ++dy)
      for (int dx = -ring; dx <= ring; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != ring || !contains_local(centre_col + dx, centre_row + dy))
          continue;
        const std::size_t c = cell(centre_col + dx, centre_row + dy);
        for (std::uint32_t i = begin_[c]; i < begin_[c + 1]; ++i) {
          const Surface& s = surfaces_[i];
          const bool usable = standing == Standing::kTraversable ? s.traversable : !s.vertical;
          const double difference = std::abs(static_cast<double>(s.top) - z);
          if (usable && difference <= best_difference) {
            best_difference = difference;
            best = i;
          }
        }
      }
    if (best)
      return best;
  }
  return std::nullopt;
}

void SurfaceGrid::drive_over_seams() {
  const auto robot_height = static_cast<float>(config_.robot_height);
  const auto continues = [&](int col, int row, const Surface& s) {
    return step_onto(col, row, s.top, s.variance).has_value();
  };
  std::vector<std::uint32_t> seams;  // marked after the search: a seam does not continue another
  for (int row = 0; row < region_.height; ++row)
    for (int col = 0; col < region_.width; ++col) {
      const std::size_t c = cell(col, row);
      for (std::uint32_t i = begin_[c]; i < begin_[c + 1]; ++i) {
        const Surface& s = surfaces_[i];
        if (!s.vertical || s.traversable)
          continue;
        if (i + 1 < begin_[c + 1] && surfaces_[i + 1].bottom - s.top < robot_height)
          continue;
        if ((continues(col - 1, row, s) && continues(col + 1, row, s)) ||
            (continues(col, row - 1, s) && continues(col, row + 1, s)))
          seams.push_back(i);
      }
    }
  for (const std::uint32_t i : seams)
    surfaces_[i].traversable = true;
}

void SurfaceGrid::classify() {
  const auto robot_height = static_cast<float>(config_.robot_height);
  const double max_gradient = std::tan(config_.max_slope);
  // The gradient, metres per cell, of the plane fitted by least squares to the surface and the heights
  // its neighbours within two cells have near it: within a climbable step plus the steepest slope over
  // their distance (what lies beyond a step is the step rule's to judge: the landing beside a stair is
  // flat). Not differences of single cells: sparse rings leave a cell one neighbour on an axis, and a
  // lidar's floor scatters some centimetres from cell to cell (its pose's tilt error times the range),
  // which single differences read as 20 degree slopes on flat ground and ramps; the plane through up to
  // 25 heights does not. Each height weighs by how sure the map is of it, and the neighbours within reach
  // are those within a step, a slope and what their uncertainty explains: a ramp's ring seen once from
  // the deck 12 m away, 0.1-0.25 m low (sigma 0.12-0.22 m), fitted a plane of its own across the ramp,
  // too steep, and closed it (issue 58: the lidar demo's ramp goals); so, the certain cells decide.
  const double max_step = config_.max_step;
  const double gradient_per_cell = max_gradient * cell_size_;
  // The plane's gradient, and on which sides of the cell its neighbours lie (kLeft | kRight | ...).
  enum Side : unsigned { kLeft = 1U, kRight = 2U, kBelow = 4U, kAbove = 8U, kEverySide = 15U };
  struct Plane {
    double gradient = 0.0;
    double sigma = 0.0;  ///< the gradient's standard error, from the heights' variances
    unsigned sides = 0U;
  };
  const auto weight = [](float variance) {
    return kSureVariance / (kSureVariance + static_cast<double>(variance));
  };
  const auto fit_plane = [&](int col, int row, const Surface& surface) {
    Plane plane;
    const float height = surface.top;
    // The surface itself is at (0, 0, 0).
    double n = weight(surface.variance);
    double sx = 0.0, sy = 0.0, sz = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0, sxz = 0.0, syz = 0.0;
    for (int dr = -2; dr <= 2; ++dr)
      for (int dc = -2; dc <= 2; ++dc) {
        const Surface* other =
            dr == 0 && dc == 0 ? nullptr : neighbour(col + dc, row + dr, height, surface.vertical);
        if (other == nullptr)
          continue;
        const double x = dc, y = dr, z = static_cast<double>(other->top - height);
        // Within max_step is within reach whatever the variances (most neighbours): step_limit's square
        // root only beyond.
        const double slope_reach = gradient_per_cell * std::max(std::abs(dc), std::abs(dr));
        if (std::abs(z) > max_step + slope_reach &&
            std::abs(z) > max_step + slope_reach +
                              std::min(config_.max_uncertain_step,
                                       config_.step_sigmas *
                                           std::sqrt(std::max(
                                               0.0, static_cast<double>(surface.variance + other->variance) -
                                                        2.0 * kSureReach))))
          continue;
        const double w = weight(other->variance);
        n += w;
        sx += w * x, sy += w * y, sz += w * z, sxx += w * x * x, syy += w * y * y, sxy += w * x * y;
        sxz += w * x * z, syz += w * y * z;
        plane.sides |=
            (dc < 0 ? kLeft : 0U) | (dc > 0 ? kRight : 0U) | (dr < 0 ? kBelow : 0U) | (dr > 0 ? kAbove : 0U);
      }
    const double cxx = sxx - sx * sx / n, cyy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    const double cxz = sxz - sx * sz / n, cyz = syz - sy * sz / n;
    const double det = cxx * cyy - cxy * cxy;
    // The weights are inverse variances over kSureVariance: the gradient's covariance is kSureVariance
    // times the inverse of the weighted moments.
    if (det > 1e-6) {
      const double gx = (cyy * cxz - cxy * cyz) / det, gy = (cxx * cyz - cxy * cxz) / det;
      plane.gradient = std::hypot(gx, gy);
      if (plane.gradient > 0.0) {  // along the gradient: u' C^-1 u, C^-1 = [cyy -cxy; -cxy cxx] / det
        const double ux = gx / plane.gradient, uy = gy / plane.gradient;
        plane.sigma = std::sqrt(kSureVariance * (cyy * ux * ux - 2.0 * cxy * ux * uy + cxx * uy * uy) / det);
      }
    } else {  // the neighbours on one line (or none): its gradient per axis (on a diagonal, sqrt(2) too
              // steep)
      const double gx = cxx > 1e-9 ? cxz / cxx : 0.0, gy = cyy > 1e-9 ? cyz / cyy : 0.0;
      plane.gradient = std::hypot(gx, gy);
      const double vx = cxx > 1e-9 ? kSureVariance / cxx : 0.0, vy = cyy > 1e-9 ? kSureVariance / cyy : 0.0;
      if (plane.gradient > 0.0)
        plane.sigma = std::sqrt((gx * gx * vx + gy * gy * vy)) / plane.gradient;
    }
    return plane;
  };
  for (int row = 0; row < region_.height; ++row)
    for (int col = 0; col < region_.width; ++col) {
      const std::size_t index = cell(col, row);
      const std::uint32_t begin = begin_[index];
      const std::uint32_t end = begin_[index + 1];
      for (std::uint32_t i = begin; i < end; ++i) {
        Surface& s = surfaces_[i];
        if (s.driven && !s.vertical) {
          s.traversable = true;
          continue;
        }
        if (i + 1 < end && surfaces_[i + 1].bottom - s.top < robot_height)
          continue;  // the patch above leaves too little room
        // A vertical patch is a slab, not a wall, where level ground or other slabs continue its top on
        // every side: a bridge deck or an upper floor, seen from below as well as from above, is one
        // patch from its underside to its top (the gap rule), and stood as a wall across the deck (issue
        // 58: no goal on the campus bridge). A wall's top, a curb or a drop's edge has ground at its
        // height on one side at most.
        const Plane plane = fit_plane(col, row, s);
        if (s.vertical && plane.sides != kEverySide)
          continue;
        // Too steep beyond what the heights' uncertainty explains, as a step is (step_sigmas).
        s.traversable = plane.gradient - config_.step_sigmas * plane.sigma <= gradient_per_cell;
      }
    }
}

}  // namespace strata

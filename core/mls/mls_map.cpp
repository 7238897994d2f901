#include "core/mls/mls_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace strata {
namespace {

// Points beyond this (a broken pose, a corrupt scan) would overflow the integer cell indices: dropped.
constexpr double kMaxCoordinate = 1.0e6;

bool usable(const Eigen::Vector3d& p) {
  return p.allFinite() && p.cwiseAbs().maxCoeff() < kMaxCoordinate;
}

/// Heights spanning more than tau without a gap: the patch becomes a vertical structure from its lowest
/// to its highest point; a new top takes the height's variance.
void extend_patch(MlsPatch& patch, float z, float variance) {
  const float top = std::max(patch.top(), z);
  const float bottom = std::min(patch.bottom(), z);
  if (z >= patch.top())
    patch.variance = variance;
  patch.mean = top;
  patch.depth = top - bottom;
}

float gap_between(const MlsPatch& patch, float z) {
  if (z > patch.top())
    return z - patch.top();
  if (z < patch.bottom())
    return patch.bottom() - z;
  return 0.0F;
}

}  // namespace

MlsMap::MlsMap(MlsConfig config) : config_(config), inverse_resolution_(1.0 / config.resolution) {}

// Moves hand the tiles over; the lookup cache must not keep pointing at tiles the source no longer owns.
MlsMap::MlsMap(MlsMap&& other) noexcept
    : config_(other.config_),
      inverse_resolution_(other.inverse_resolution_),
      version_(other.version_),
      tiles_(std::move(other.tiles_)) {
  other.tiles_.clear();
  other.cached_key_ = ~0ULL;
  other.cached_tile_ = nullptr;
}

MlsMap& MlsMap::operator=(MlsMap&& other) noexcept {
  if (this != &other) {
    config_ = other.config_;
    inverse_resolution_ = other.inverse_resolution_;
    version_ = other.version_;
    tiles_ = std::move(other.tiles_);
    cached_key_ = ~0ULL;
    cached_tile_ = nullptr;
    other.tiles_.clear();
    other.cached_key_ = ~0ULL;
    other.cached_tile_ = nullptr;
  }
  return *this;
}

CellIndex MlsMap::cell_of(double x, double y) const {
  return {static_cast<int>(std::floor(x * inverse_resolution_)),
          static_cast<int>(std::floor(y * inverse_resolution_))};
}

Eigen::Vector2d MlsMap::cell_center(CellIndex cell) const {
  return {(cell.x + 0.5) * config_.resolution, (cell.y + 0.5) * config_.resolution};
}

TileIndex MlsMap::tile_of(CellIndex cell) {
  // Arithmetic shift: floor division for negative indices too (C++20 defines it).
  return {cell.x >> kMlsTileBits, cell.y >> kMlsTileBits};
}

int MlsMap::local_index(CellIndex cell) {
  return (cell.y & (kMlsTileSize - 1)) * kMlsTileSize + (cell.x & (kMlsTileSize - 1));
}

std::uint64_t MlsMap::key_of(TileIndex tile) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(tile.x)) << 32U) |
         static_cast<std::uint32_t>(tile.y);
}

TileIndex MlsMap::tile_from_key(std::uint64_t key) {
  return {static_cast<int>(static_cast<std::uint32_t>(key >> 32U)),
          static_cast<int>(static_cast<std::uint32_t>(key & 0xFFFFFFFFULL))};
}

MlsTile& MlsMap::tile_for(TileIndex tile) {
  const std::uint64_t key = key_of(tile);
  if (cached_tile_ != nullptr && key == cached_key_)  // ~0 is a real key: tile (-1, -1)
    return *cached_tile_;
  std::unique_ptr<MlsTile>& slot = tiles_[key];
  if (!slot)
    slot = std::make_unique<MlsTile>();
  cached_key_ = key;
  cached_tile_ = slot.get();
  return *slot;
}

const MlsTile* MlsMap::find_tile(TileIndex tile) const {
  const auto it = tiles_.find(key_of(tile));
  return it == tiles_.end() ? nullptr : it->second.get();
}

MlsInsertStats MlsMap::insert_scan(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
                                   const std::optional<Eigen::Vector3d>& robot_ground) {
  ++version_;
  MlsInsertStats stats;
  stats.points = points.size();
  if (!usable(sensor_origin)) {
    stats.points_dropped = points.size();
    return stats;
  }

  // Free space first, against the map as it was: a surface this scan sees through loses evidence before
  // this scan's own hits add to the surfaces it does see.
  if (config_.free_space_ray_stride > 0) {
    const auto stride = static_cast<std::size_t>(config_.free_space_ray_stride);
    for (std::size_t i = 0; i < points.size(); i += stride)
      if (usable(points[i]) && (points[i] - sensor_origin).norm() >= config_.min_range)
        trace_ray(sensor_origin, points[i], stats);
  }

  const double sigma_base = config_.sigma_base;
  const double sigma_per_metre = config_.sigma_per_metre;
  for (const Eigen::Vector3d& p : points) {
    if (!usable(p)) {
      ++stats.points_dropped;
      continue;
    }
    const double range = (p - sensor_origin).norm();
    if (range < config_.min_range) {
      ++stats.points_dropped;
      continue;
    }
    const double sigma = sigma_base + sigma_per_metre * range;
    const CellIndex cell = cell_of(p.x(), p.y());
    MlsTile& tile = tile_for(tile_of(cell));
    tile.version = version_;
    if (!add_point(tile, local_index(cell), static_cast<float>(p.z()), static_cast<float>(sigma * sigma)))
      ++stats.points_dropped;
  }
  if (robot_ground && stats.points_dropped < stats.points)  // a scan of nothing usable changes nothing
    stats.driven_cells = drive_to(*robot_ground, version_, static_cast<float>(sensor_origin.z()));
  return stats;
}

std::size_t MlsMap::drive_to(const Eigen::Vector3d& ground, std::uint64_t version,
                             std::optional<float> body_top) {
  if (!usable(ground))
    return 0;
  const std::size_t changed = mark_way(ground, version) + mark_ground(ground, version, body_top);
  last_driven_ = ground;
  return changed;
}

std::size_t MlsMap::mark_way(const Eigen::Vector3d& ground, std::uint64_t version) {
  if (!last_driven_ || !usable(ground))
    return 0;
  const Eigen::Vector3d way = ground - *last_driven_;
  const double length = way.norm();
  if (!(length <= config_.driven_stride))
    return 0;
  // Footprints half a cell apart, short of both ends (their own footprints mark those): a band as wide as
  // one, and a track (kTrack) with no cell skipped. A cell apart, rounding put two in one cell and skipped
  // the next, and a gap in the track between edges closed it (issue 58).
  const int steps = static_cast<int>(std::ceil(2.0 * length * inverse_resolution_));
  std::size_t changed = 0;
  for (int i = 1; i < steps; ++i)
    changed += mark_ground(*last_driven_ + way * (static_cast<double>(i) / steps), version);
  return changed;
}

bool MlsMap::insert_after_patch(MlsTile& tile, MlsTile::Handle& head, MlsTile::Handle after,
                                const MlsPatch& patch) {
  const MlsTile::Handle handle = tile.allocate(patch);
  if (handle == 0)
    return false;
  MlsTile::Handle& link = after == 0 ? head : tile.at(after).next;
  tile.at(handle).next = link;
  link = handle;
  return true;
}

bool MlsMap::add_point(MlsTile& tile, int local, float z, float variance) {
  const auto gamma = static_cast<float>(config_.gap);
  MlsTile::Handle& head = tile.first[static_cast<std::size_t>(local)];

  MlsTile::Handle best = 0;
  MlsTile::Handle below_best = 0;
  MlsTile::Handle insert_after = 0;  // the highest patch below z, for a new patch
  float best_gap = std::numeric_limits<float>::infinity();
  MlsTile::Handle previous = 0;
  for (MlsTile::Handle h = head; h != 0; previous = h, h = tile.at(h).next) {
    const MlsPatch& patch = tile.at(h);
    const float gap = gap_between(patch, z);
    if (gap < best_gap) {
      best_gap = gap;
      best = h;
      below_best = previous;
    }
    if (patch.mean < z)
      insert_after = h;
  }

  if (best == 0 || best_gap >= gamma) {
    // The gap rule: far enough from every surface of the cell to be a surface of its own.
    MlsPatch fresh;
    fresh.mean = z;
    fresh.variance = variance;
    fresh.evidence = 1;
    return insert_after_patch(tile, head, insert_after, fresh);
  }

  MlsPatch& patch = tile.at(best);
  // A horizontal patch takes a point within tau, or within three standard deviations (at most twice tau)
  // when the two are less certain than that: floor seen from afar by a moving sensor scatters beyond tau
  // (its pose's tilt error times the range), and stood as vertical patches all over open ground.
  // A point less certain than the horizontal patch it meets (seen from further than the points that made
  // it) is taken within three of its own standard deviations, up to 4 tau: floor mapped from near and then
  // seen again 20-30 m away at a grazing angle, with its pose's tilt error times the range, stood as
  // vertical patches 0.2-0.3 m deep across a hallway and cut the robot's way (docs/benchmarks.md, "Far
  // floor"). What stands higher than that still makes the patch vertical, and a nearer scan is as strict
  // as before.
  const auto tau = static_cast<float>(config_.vertical_threshold);
  float tolerance = std::clamp(3.0F * std::sqrt(patch.variance + variance), tau, 2.0F * tau);
  if (patch.variance < variance)
    tolerance = std::max(tolerance, std::min(3.0F * std::sqrt(variance), 4.0F * tau));
  if (!patch.vertical() && std::abs(z - patch.mean) <= tolerance) {
    // Kalman update of the height (thesis / Triebel 2006): the less certain estimate moves more.
    const float sum = patch.variance + variance;
    patch.mean = (variance * patch.mean + patch.variance * z) / sum;
    patch.variance = patch.variance * variance / sum;
  } else if (patch.vertical() && z > patch.top() && z - patch.top() <= tolerance) {
    // The top of a vertical patch is a surface as well (a slab's: a bridge deck seen from below and from
    // above): a point above it within the noise of the two refines it as a horizontal patch's height is
    // refined. Raised to every point above, it stood at the highest noise seen, up to 0.12 m above the
    // deck around it: a step no wheel takes (issue 58). Points below the top are inside the patch and
    // never lower it, so a curb is no lower than its points say.
    const float bottom = patch.bottom();
    const float sum = patch.variance + variance;
    patch.mean = (variance * patch.mean + patch.variance * z) / sum;
    patch.variance = patch.variance * variance / sum;
    patch.depth = patch.mean - bottom;
  } else {
    extend_patch(patch, z, variance);
  }
  if (patch.evidence < config_.max_evidence)
    ++patch.evidence;

  // The patch grew: it may now be closer than gamma to its neighbours, which makes them one structure.
  const MlsTile::Handle above = patch.next;
  if (above != 0 && tile.at(above).bottom() - patch.top() < gamma)
    merge_into(tile, best, above);
  if (below_best != 0 && tile.at(best).bottom() - tile.at(below_best).top() < gamma)
    merge_into(tile, below_best, best);
  return true;
}

void MlsMap::merge_into(MlsTile& tile, MlsTile::Handle lower, MlsTile::Handle upper) {
  MlsPatch& low = tile.at(lower);
  const MlsPatch& high = tile.at(upper);
  const float top = std::max(low.top(), high.top());
  const float bottom = std::min(low.bottom(), high.bottom());
  low.variance = high.variance;
  low.mean = top;
  low.depth = top - bottom;
  low.evidence = std::max(low.evidence, high.evidence);
  low.flags |= high.flags;
  low.next = high.next;
  tile.release(upper);
}

void MlsMap::trace_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& end, MlsInsertStats& stats) {
  const Eigen::Vector3d delta = end - origin;
  const double horizontal = delta.head<2>().norm();
  if (horizontal <= config_.free_space_stop_short + config_.resolution)
    return;
  ++stats.rays_traced;
  const double t_stop = (horizontal - config_.free_space_stop_short) / horizontal;
  const auto margin = static_cast<float>(config_.free_space_height_margin);
  const auto end_z = static_cast<float>(end.z());

  // Amanatides-Woo walk over the 2D cells the ray's ground projection crosses, parameter t in [0, 1].
  const double ox = origin.x() * inverse_resolution_;
  const double oy = origin.y() * inverse_resolution_;
  const double dx = delta.x() * inverse_resolution_;
  const double dy = delta.y() * inverse_resolution_;
  CellIndex cell{static_cast<int>(std::floor(ox)), static_cast<int>(std::floor(oy))};
  const int step_x = dx > 0 ? 1 : -1;
  const int step_y = dy > 0 ? 1 : -1;
  const double infinity = std::numeric_limits<double>::infinity();
  const double t_delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : infinity;
  const double t_delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : infinity;
  double t_max_x = dx != 0.0 ? ((cell.x + (dx > 0 ? 1 : 0)) - ox) / dx : infinity;
  double t_max_y = dy != 0.0 ? ((cell.y + (dy > 0 ? 1 : 0)) - oy) / dy : infinity;

  // The walk keeps its place within the tile and looks the tile up only when it steps out of one (a
  // tile is 32 cells across): the key and lookup per cell were a quarter of a ray's instructions, and
  // ray tracing is a fifth of a 32-beam revolution's processing (docs/benchmarks.md, "Real captures").
  // find_tile is the const lookup; the map is this one's own, non-const, and the ray clears patches.
  const auto tile_at = [this](CellIndex c) { return const_cast<MlsTile*>(find_tile(tile_of(c))); };
  constexpr int kLocalMask = kMlsTileSize - 1;
  MlsTile* tile = tile_at(cell);
  int local_x = cell.x & kLocalMask;
  int local_y = cell.y & kLocalMask;
  std::size_t visited = 0;
  double t = 0.0;
  auto z0 = static_cast<float>(origin.z());
  while (t < t_stop) {
    const double t_next = std::min({t_max_x, t_max_y, t_stop});
    const auto z1 = static_cast<float>(origin.z() + delta.z() * t_next);
    ++visited;
    if (tile != nullptr) {
      const float low = std::min(z0, z1);
      const float high = std::max(z0, z1);
      MlsTile::Handle* link = &tile->first[static_cast<std::size_t>(local_y * kMlsTileSize + local_x)];
      while (*link != 0) {
        const MlsTile::Handle h = *link;
        MlsPatch& patch = tile->at(h);
        const bool crossed = high >= patch.bottom() && low <= patch.top();
        const bool ends_elsewhere = patch.vertical() || std::abs(end_z - patch.mean) > margin;
        // Ground the robot stood on is no surface a ray passes through: a ray "through" it is the pose's
        // tilt error (a deck seen ahead, 0.15 m low, had its driven cells cleared one by one, and a gap
        // in the track closed the way; issue 58). What rises from it (a vertical patch) can still go.
        const bool stood_on = patch.driven() && !patch.vertical();
        if (crossed && ends_elsewhere && !stood_on) {
          tile->version = version_;
          if (--patch.evidence == 0) {
            *link = patch.next;
            tile->release(h);
            ++stats.patches_cleared;
            continue;
          }
        }
        link = &patch.next;
      }
    }
    t = t_next;
    z0 = z1;
    if (t_max_x < t_max_y) {
      cell.x += step_x;
      t_max_x += t_delta_x;
      local_x += step_x;
      if ((local_x & ~kLocalMask) != 0) {  // stepped out of the tile
        local_x &= kLocalMask;
        tile = tile_at(cell);
      }
    } else {
      cell.y += step_y;
      t_max_y += t_delta_y;
      local_y += step_y;
      if ((local_y & ~kLocalMask) != 0) {
        local_y &= kLocalMask;
        tile = tile_at(cell);
      }
    }
  }
  stats.cells_visited_by_rays += visited;
}

std::size_t MlsMap::mark_driven(const Eigen::Vector3d& ground) {
  const std::size_t changed = mark_ground(ground, version_ + 1);
  if (changed > 0)
    ++version_;
  return changed;
}

std::size_t MlsMap::mark_passed(const Eigen::Vector3d& ground) {
  const std::size_t changed = drive_to(ground, version_ + 1);
  if (changed > 0)
    ++version_;
  return changed;
}

std::size_t MlsMap::mark_ground(const Eigen::Vector3d& ground, std::uint64_t version,
                                std::optional<float> body_top) {
  if (!usable(ground) || !(config_.driven_radius > 0.0))
    return 0;
  const auto z = static_cast<float>(ground.z());
  const auto tolerance = static_cast<float>(config_.driven_tolerance);
  const auto gamma = static_cast<float>(config_.gap);
  const int reach = static_cast<int>(std::ceil(config_.driven_radius * inverse_resolution_));
  const CellIndex centre = cell_of(ground.x(), ground.y());
  const double radius_squared = config_.driven_radius * config_.driven_radius;
  std::vector<CellIndex> footprint;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      const CellIndex cell{centre.x + dx, centre.y + dy};
      if ((cell_center(cell) - ground.head<2>()).squaredNorm() <= radius_squared)
        footprint.push_back(cell);
    }
  // The ground where the scanner did not see it is as high as where it did: the median of the surfaces
  // found at the robot's ground, else the robot's own estimate. Measured heights are the better ones (the
  // pose's height drifts), and one footprint at two heights would be a step the robot cannot climb.
  std::vector<float> seen;
  for (const CellIndex& cell : footprint) {
    const MlsTile* tile = find_tile(tile_of(cell));
    if (tile != nullptr)
      tile->for_each_patch(local_index(cell), [&](const MlsPatch& patch) {
        if (!patch.vertical() && std::abs(patch.top() - z) <= tolerance)
          seen.push_back(patch.top());
      });
  }
  float fill = z;
  if (!seen.empty()) {
    const auto middle = seen.begin() + static_cast<std::ptrdiff_t>(seen.size() / 2);
    std::nth_element(seen.begin(), middle, seen.end());
    fill = *middle;
  }
  std::size_t changed = 0;
  for (const CellIndex& cell : footprint) {
    const auto marks = static_cast<std::uint8_t>(
        cell.x == centre.x && cell.y == centre.y ? MlsPatch::kDriven | MlsPatch::kTrack : MlsPatch::kDriven);
    MlsTile& tile = tile_for(tile_of(cell));  // a new tile always gets the patch below
    MlsTile::Handle& head = tile.first[static_cast<std::size_t>(local_index(cell))];
    bool cell_changed = false;
    if (body_top) {
      // Where the robot stands nothing else is: what lies wholly between its ground and its sensor is
      // its own body (a car's bonnet, seen by the lidar on its roof) or something that has moved away.
      for (MlsTile::Handle* link = &head; *link != 0;) {
        const MlsPatch& patch = tile.at(*link);
        if (patch.bottom() > z + tolerance && patch.top() <= *body_top && !patch.driven()) {
          const MlsTile::Handle gone = *link;
          *link = patch.next;
          tile.release(gone);
          cell_changed = true;
          continue;
        }
        link = &tile.at(*link).next;
      }
    }
    MlsTile::Handle standing = 0;
    MlsTile::Handle insert_after = 0;
    bool in_the_way = false;
    for (MlsTile::Handle h = head; h != 0; h = tile.at(h).next) {
      const MlsPatch& patch = tile.at(h);
      if (std::abs(patch.top() - z) <= tolerance)
        standing = h;
      else if (patch.top() < fill)
        insert_after = h;
      else if (patch.bottom() - fill < gamma)
        in_the_way = true;  // a surface just above the ground, or reaching through it
    }
    if (standing != 0) {
      MlsPatch& patch = tile.at(standing);
      cell_changed = cell_changed || (patch.flags & marks) != marks;
      patch.flags |= marks;
    } else if (!in_the_way && insert_after != 0 && fill - tile.at(insert_after).top() < gamma &&
               !seen.empty()) {
      // A surface less than gamma below the ground the footprint shows elsewhere, seen from beneath: a
      // bridge deck's underside, its seam's face with the plateau, seen from the road under it (issue
      // 58: a line of such cells across the deck closed the way back). What the robot stands on hid
      // their top. A point at the ground would make the patch reach up to it (add_point), and so does
      // the robot.
      MlsPatch& patch = tile.at(insert_after);
      extend_patch(patch, fill, tolerance * tolerance);
      patch.flags |= marks;
      cell_changed = true;
    } else if (!in_the_way && (insert_after == 0 || fill - tile.at(insert_after).top() >= gamma)) {
      // A gap the robot's ground can sit in (elsewhere the measurements are left be): a new patch.
      MlsPatch fresh;
      fresh.mean = fill;
      fresh.variance = tolerance * tolerance;
      fresh.evidence = static_cast<std::uint8_t>(config_.max_evidence);  // the wheels are on it
      fresh.flags = marks;
      cell_changed = insert_after_patch(tile, head, insert_after, fresh) || cell_changed;
    }
    if (cell_changed) {
      ++changed;
      tile.version = version;
    }
  }
  return changed;
}

std::vector<MlsPatch> MlsMap::patches(CellIndex cell) const {
  std::vector<MlsPatch> out;
  if (const MlsTile* tile = find_tile(tile_of(cell)))
    tile->for_each_patch(local_index(cell), [&](const MlsPatch& patch) {
      out.push_back(patch);
      out.back().next = 0;
    });
  return out;
}

std::vector<TileIndex> MlsMap::tiles_changed_since(std::uint64_t version) const {
  std::vector<TileIndex> out;
  for (const auto& [key, tile] : tiles_)
    if (tile->version > version)
      out.push_back(tile_from_key(key));
  return out;
}

std::vector<TileIndex> MlsMap::tile_indices() const {
  std::vector<TileIndex> out;
  out.reserve(tiles_.size());
  for (const auto& entry : tiles_)
    out.push_back(tile_from_key(entry.first));
  return out;
}

std::size_t MlsMap::occupied_cell_count() const {
  std::size_t count = 0;
  for (const auto& entry : tiles_)
    count += static_cast<std::size_t>(
        std::count_if(entry.second->first.begin(), entry.second->first.end(), [](auto h) { return h != 0; }));
  return count;
}

std::size_t MlsMap::patch_count() const {
  std::size_t count = 0;
  for (const auto& entry : tiles_)
    for (int i = 0; i < kMlsTileCells; ++i)
      entry.second->for_each_patch(i, [&](const MlsPatch&) { ++count; });
  return count;
}

std::size_t MlsMap::memory_bytes() const {
  constexpr std::size_t kMallocOverhead = 16;
  // libstdc++ node: next pointer, key, value (no cached hash for a "fast" hash), plus malloc overhead.
  constexpr std::size_t kNode = sizeof(void*) + sizeof(std::uint64_t) + sizeof(void*) + kMallocOverhead;
  std::size_t bytes = sizeof(*this) + tiles_.bucket_count() * sizeof(void*);
  for (const auto& entry : tiles_)
    bytes += kNode + sizeof(MlsTile) + kMallocOverhead + entry.second->pool.capacity() * sizeof(MlsPatch) +
             (entry.second->pool.capacity() > 0 ? kMallocOverhead : 0);
  return bytes;
}

bool MlsMap::same_content(const MlsMap& other) const {
  const MlsConfig& a = config_;
  const MlsConfig& b = other.config_;
  if (a.resolution != b.resolution || a.gap != b.gap || a.vertical_threshold != b.vertical_threshold ||
      a.sigma_base != b.sigma_base || a.sigma_per_metre != b.sigma_per_metre || a.min_range != b.min_range ||
      a.max_evidence != b.max_evidence || a.free_space_ray_stride != b.free_space_ray_stride ||
      a.free_space_stop_short != b.free_space_stop_short ||
      a.free_space_height_margin != b.free_space_height_margin)
    return false;
  if (version_ != other.version_ || tiles_.size() != other.tiles_.size())
    return false;
  for (const auto& [key, tile] : tiles_) {
    const auto it = other.tiles_.find(key);
    if (it == other.tiles_.end() || it->second->version != tile->version)
      return false;
    const MlsTile& mine = *tile;
    const MlsTile& theirs = *it->second;
    for (std::size_t i = 0; i < kMlsTileCells; ++i) {
      MlsTile::Handle h = mine.first[i];
      MlsTile::Handle g = theirs.first[i];
      for (; h != 0 && g != 0; h = mine.at(h).next, g = theirs.at(g).next) {
        const MlsPatch& p = mine.at(h);
        const MlsPatch& q = theirs.at(g);
        if (std::memcmp(&p.mean, &q.mean, sizeof(float)) != 0 ||
            std::memcmp(&p.variance, &q.variance, sizeof(float)) != 0 ||
            std::memcmp(&p.depth, &q.depth, sizeof(float)) != 0 || p.evidence != q.evidence ||
            p.flags != q.flags)
          return false;
      }
      if (h != 0 || g != 0)
        return false;
    }
  }
  return true;
}

bool MlsMap::append_patch(CellIndex cell, const MlsPatch& patch) {
  MlsTile& tile = tile_for(tile_of(cell));
  MlsPatch copy = patch;
  copy.next = 0;
  const MlsTile::Handle handle = tile.allocate(copy);
  if (handle == 0)
    return false;
  MlsTile::Handle* link = &tile.first[static_cast<std::size_t>(local_index(cell))];
  while (*link != 0)
    link = &tile.at(*link).next;
  *link = handle;
  return true;
}

void MlsMap::set_tile_version(TileIndex tile, std::uint64_t version) {
  tile_for(tile).version = version;
}

}  // namespace strata

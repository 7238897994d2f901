#include "server/pipeline/live_map.hpp"

#include <chrono>
#include <cmath>
#include <utility>

#include "server/encoding/occupancy_png.hpp"

namespace strata::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// The slope of a patch is estimated from the cells two away on each axis: a region classified with this
/// margin gives the changed tiles' border cells the same flags as their interior.
constexpr int kClassificationMargin = 2;

CellRegion grown(const CellRegion& region, int margin) {
  if (region.width <= 0 || region.height <= 0)
    return region;
  return {
      {region.min.x - margin, region.min.y - margin}, region.width + 2 * margin, region.height + 2 * margin};
}

/// Height of the level the robot is on: the surface the fill reached in the robot's cell, else the
/// robot's own ground height.
double level_height(const LevelGrid& grid, const Eigen::Vector3d& robot_ground) {
  const float height = grid.surface_height_at(robot_ground.x(), robot_ground.y());
  return std::isfinite(height) ? static_cast<double>(height) : robot_ground.z();
}

}  // namespace

LiveMap::LiveMap(LiveMapOptions options) : options_(std::move(options)), map_(options_.mls) {
  snapshot_ = std::make_shared<const MapSnapshot>();
}

MappingTimes LiveMap::insert_scan(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
                                  const Eigen::Vector3d& robot_ground, double received_at) {
  MappingTimes times;
  received_at_ = received_at;
  if (!pending_since_)
    pending_since_ = map_.version();
  const auto start = Clock::now();
  // With the ground under the robot marked driven: it never strands itself (issue 21).
  map_.insert_scan(points, sensor_origin, robot_ground);
  times.insert_ms = ms_since(start);
  robot_ground_ = robot_ground;
  return times;
}

bool LiveMap::refresh_pending(MappingTimes& times) {
  if (!pending_since_ || !robot_ground_)
    return false;
  const std::uint64_t since = std::exchange(pending_since_, std::nullopt).value();
  refresh(changed_region(map_, since, *robot_ground_), since, times);
  return true;
}

void LiveMap::mark_passed(const Eigen::Vector3d& robot_ground) {
  if (!pending_since_)
    pending_since_ = map_.version();
  map_.mark_passed(robot_ground);
}

bool LiveMap::follow_robot(const Eigen::Vector3d& robot_ground, double radius, double every) {
  if (followed_from_ && (robot_ground - *followed_from_).norm() < every)
    return false;
  followed_from_ = robot_ground;
  robot_ground_ = robot_ground;
  received_at_ = 0.0;
  const CellIndex low = map_.cell_of(robot_ground.x() - radius, robot_ground.y() - radius);
  const CellIndex high = map_.cell_of(robot_ground.x() + radius, robot_ground.y() + radius);
  const CellRegion region{low, high.x - low.x + 1, high.y - low.y + 1};
  // A new version, as for any new drivable map (its image and the ROS download are named by versions);
  // no tile changed, so none is encoded again.
  map_.set_version(map_.version() + 1);
  MappingTimes times;
  refresh(region, map_.version(), times);
  return true;
}

void LiveMap::replace(MlsMap map, Replacement why) {
  const std::uint64_t version = std::max(map.version(), map_.version()) + 1;
  map.set_version(version);
  for (const TileIndex& tile : map.tile_indices())
    map.set_tile_version(tile, version);
  // Tiles the new map does not have stay as empty ones with the new version: a client removes a tile when
  // an empty one arrives, and would otherwise keep drawing what is gone.
  for (const TileIndex& tile : map_.tile_indices())
    if (map.find_tile(tile) == nullptr)
      map.set_tile_version(tile, version);
  // All or nothing: a map whose drivable map and tiles cannot be made (out of memory) leaves the live map
  // as it was, rather than half replaced with every later update failing on it.
  // What was inserted into the old map is gone with it; the refresh below covers the whole new one.
  const std::optional<std::uint64_t> previous_pending = std::exchange(pending_since_, std::nullopt);
  MlsMap previous = std::exchange(map_, std::move(map));
  auto previous_tiles = std::exchange(tiles_, {});
  const std::optional<DrivableMap> previous_drivable = drivable_;
  const std::shared_ptr<const EncodedOccupancy> previous_occupancy = occupancy_;
  const std::optional<Eigen::Vector3d> previous_followed_from = std::exchange(followed_from_, std::nullopt);
  const double previous_received_at = std::exchange(received_at_, 0.0);  // not from a scan
  if (why == Replacement::kRebuilt)
    ++rebuilds_;
  try {
    MappingTimes times;
    const CellRegion all = CellRegion::of_tiles(map_.tile_indices());
    const CellRegion region =
        robot_ground_ ? CellRegion::bounding(all, changed_region(map_, version, *robot_ground_)) : all;
    refresh(region, version - 1, times);
  } catch (...) {
    map_ = std::move(previous);
    tiles_ = std::move(previous_tiles);
    drivable_ = previous_drivable;
    occupancy_ = previous_occupancy;
    followed_from_ = previous_followed_from;
    received_at_ = previous_received_at;
    pending_since_ = previous_pending;
    if (why == Replacement::kRebuilt)
      --rebuilds_;
    throw;
  }
}

void LiveMap::refresh(const CellRegion& region, std::uint64_t since, MappingTimes& times) {
  auto start = Clock::now();
  const SurfaceGrid surfaces(map_, grown(region, kClassificationMargin), options_.traversability);
  if (robot_ground_) {
    drivable_ = compute_drivable_map(map_, surfaces, options_.traversability, *robot_ground_);
    times.region_cells = drivable_->grid.cells.size();
  }
  times.drivable_ms = ms_since(start);

  start = Clock::now();
  const std::vector<TileIndex> changed = map_.tiles_changed_since(since);
  times.changed_tiles = changed.size();
  for (const TileIndex& index : changed) {
    const MlsTile* tile = map_.find_tile(index);
    if (tile == nullptr)
      continue;
    auto encoded = std::make_shared<EncodedTile>();
    encoded->tile_x = index.x;
    encoded->tile_y = index.y;
    encoded->version = tile->version;
    encoded->stamp = received_at_;
    encoded->draco = encoding::encode_tile(*tile, index, map_.resolution(), &surfaces, options_.codec);
    for (int local = 0; local < kMlsTileCells; ++local)
      tile->for_each_patch(local, [&](const MlsPatch&) { ++encoded->patches; });
    tiles_[{index.x, index.y}] = std::move(encoded);
  }
  times.tiles_ms = ms_since(start);

  start = Clock::now();
  if (drivable_) {
    auto occupancy = std::make_shared<EncodedOccupancy>(encoding::encode_occupancy_png(
        drivable_->grid, level_height(drivable_->grid, *robot_ground_), map_.version()));
    occupancy->stamp = received_at_;
    occupancy_ = std::move(occupancy);
  }
  times.png_ms = ms_since(start);

  start = Clock::now();
  auto snapshot = std::make_shared<MapSnapshot>();
  snapshot->version = map_.version();
  snapshot->tiles.reserve(tiles_.size());
  for (const auto& [key, tile] : tiles_)
    snapshot->tiles.push_back(tile);
  snapshot->occupancy = occupancy_;
  snapshot->cells = map_.occupied_cell_count();
  snapshot->patches = map_.patch_count();
  snapshot->memory_bytes = map_.memory_bytes();
  snapshot->rebuilds = rebuilds_;
  snapshot->localizing = localizing_;
  snapshot->name = name_;
  snapshot->saved_version = saved_version_;
  snapshot_ = std::move(snapshot);
  times.snapshot_ms = ms_since(start);
}

void LiveMap::rename_snapshot() {
  auto snapshot = std::make_shared<MapSnapshot>(*snapshot_);
  snapshot->name = name_;
  snapshot->saved_version = saved_version_;
  snapshot_ = std::move(snapshot);
}

LiveMap::WholeLevel LiveMap::whole_level(std::optional<std::uint64_t> version) const {
  if (version && whole_level_.drivable && whole_level_.version == *version)
    return whole_level_;
  if (version && *version != map_.version())
    return {.gone = true};
  if (whole_level_.drivable && whole_level_.version == map_.version())
    return whole_level_;
  if (!robot_ground_)
    return {};
  whole_level_ = {
      .drivable = std::make_shared<const DrivableMap>(compute_drivable_map(
          map_, options_.traversability, *robot_ground_, CellRegion::of_tiles(map_.tile_indices()))),
      .version = map_.version()};
  return whole_level_;
}

}  // namespace strata::pipeline

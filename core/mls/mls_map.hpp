#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/mls/mls_config.hpp"
#include "core/mls/mls_patch.hpp"
#include "core/mls/mls_tile.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A cell's global integer coordinates: floor(x / resolution), floor(y / resolution).
struct CellIndex {
  int x = 0;
  int y = 0;
  friend bool operator==(const CellIndex&, const CellIndex&) = default;
};

/// A tile's global integer coordinates: the cell index shifted right by kMlsTileBits.
struct TileIndex {
  int x = 0;
  int y = 0;
  friend bool operator==(const TileIndex&, const TileIndex&) = default;
};

/// What insert_scan did, for measuring and for the tests.
struct MlsInsertStats {
  std::size_t points = 0;
  std::size_t rays_traced = 0;
  std::size_t cells_visited_by_rays = 0;
  std::size_t patches_cleared = 0;  ///< removed because rays passed through them
  std::size_t points_dropped = 0;   ///< not finite, too near, too far, or a tile's pool was full
  std::size_t driven_cells = 0;     ///< cells newly marked as ground the robot stood on
};

/// Multi-Level Surface map (Triebel, Pfaff, Burgard 2006): an unbounded 2D grid of cells in tiles kept in
/// a hash map, each cell a short height-sorted list of horizontal and vertical patches. See
/// docs/architecture.md 4.2 for the rules; MlsConfig for the parameters.
class MlsMap {
 public:
  explicit MlsMap(MlsConfig config = {});
  MlsMap(MlsMap&& other) noexcept;
  MlsMap& operator=(MlsMap&& other) noexcept;
  MlsMap(const MlsMap&) = delete;
  MlsMap& operator=(const MlsMap&) = delete;
  ~MlsMap() = default;

  /// Adds a registered scan: `points` in the map frame at full resolution, `sensor_origin` where they were
  /// measured from (map frame). First traces a subsample of the rays to fade surfaces they pass through,
  /// then updates the patches with every point. Increments version() once; every tile it changes gets
  /// the new version.
  /// `robot_ground`, if given: where the robot stood when it took the scan; the ground under it is marked
  /// driven (mark_driven) under the scan's version, unless the scan had no usable point, and what the scan
  /// put between that ground and the sensor within the robot's footprint (its own body) is removed. The
  /// ground between it and the previous scan's, if within MlsConfig::driven_stride, is marked too.
  MlsInsertStats insert_scan(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
                             const std::optional<Eigen::Vector3d>& robot_ground = std::nullopt);

  /// The robot stands at `ground` (map frame, the point between its wheels): the cells within
  /// MlsConfig::driven_radius of it are ground it drove over. Each gets its surface at that height marked
  /// MlsPatch::kDriven: the horizontal patch (or the top of a low vertical one) within driven_tolerance,
  /// else a new horizontal patch there, since scanners rarely see the ground under the robot. The cell under
  /// `ground` itself is also marked MlsPatch::kTrack: the line the robot's centre followed. A cell whose
  /// patches leave no room for one (something within `gap` of the ground that is not ground) is left as
  /// it is. Returns the cells changed; when any, version() increments once and their tiles get it.
  std::size_t mark_driven(const Eigen::Vector3d& ground);
  /// The robot passed `ground` between two scans inserted (one the mapping had no time for): its footprint
  /// and the way to it from the last ground are marked as insert_scan marks them, and the next scan's way
  /// starts there. At 5x the campus demo's mapping dropped scans until two mapped ones lay 2.1 m apart, past
  /// driven_stride, and the way the robot drove onto the bridge deck stayed unmarked: a line of the deck's
  /// seam seen only from the road below closed the way back (issue 58). Returns the cells changed; when
  /// any, version() increments once.
  std::size_t mark_passed(const Eigen::Vector3d& ground);

  [[nodiscard]] const MlsConfig& config() const { return config_; }
  [[nodiscard]] double resolution() const { return config_.resolution; }
  /// Incremented by every insert_scan (and mark_driven that changed something); tile versions are values
  /// of it.
  [[nodiscard]] std::uint64_t version() const { return version_; }

  [[nodiscard]] CellIndex cell_of(double x, double y) const;
  [[nodiscard]] Eigen::Vector2d cell_center(CellIndex cell) const;
  [[nodiscard]] static TileIndex tile_of(CellIndex cell);
  [[nodiscard]] static int local_index(CellIndex cell);

  /// The patches of one cell, lowest first (a copy: for tests, exports and tools, not inner loops).
  [[nodiscard]] std::vector<MlsPatch> patches(CellIndex cell) const;
  [[nodiscard]] const MlsTile* find_tile(TileIndex tile) const;
  /// Tiles whose version is greater than `version`: what changed since a client last looked.
  [[nodiscard]] std::vector<TileIndex> tiles_changed_since(std::uint64_t version) const;
  [[nodiscard]] std::vector<TileIndex> tile_indices() const;

  [[nodiscard]] std::size_t tile_count() const { return tiles_.size(); }
  [[nodiscard]] std::size_t occupied_cell_count() const;
  [[nodiscard]] std::size_t patch_count() const;
  /// Heap bytes held by the map: tiles (cell heads and pool capacity) plus the hash table's nodes and
  /// buckets, estimated the way libstdc++ lays them out.
  [[nodiscard]] std::size_t memory_bytes() const;

  /// Same config, same version, same tiles with the same versions and the same patches per cell (pool
  /// layout and free lists do not matter).
  [[nodiscard]] bool same_content(const MlsMap& other) const;

  // For the native file reader: rebuild a map tile by tile.
  void set_version(std::uint64_t version) { version_ = version; }
  /// Appends a patch above the current top of `cell` (the caller gives patches lowest first).
  /// Returns false when the tile's pool is full.
  bool append_patch(CellIndex cell, const MlsPatch& patch);
  void set_tile_version(TileIndex tile, std::uint64_t version);

 private:
  struct TileKeyHash {
    std::size_t operator()(std::uint64_t key) const { return key * 0x9E3779B97F4A7C15ULL >> 20U; }
  };
  static std::uint64_t key_of(TileIndex tile);
  static TileIndex tile_from_key(std::uint64_t key);
  MlsTile& tile_for(TileIndex tile);

  bool add_point(MlsTile& tile, int local, float z, float variance);
  /// Puts `patch` into the cell whose first patch is `head`, just above patch `after` (0: lowest). False
  /// when the tile's pool is full.
  bool insert_after_patch(MlsTile& tile, MlsTile::Handle& head, MlsTile::Handle after, const MlsPatch& patch);
  /// mark_driven's work; the tiles it changes get `version`. With `body_top`, the patches in the footprint
  /// wholly between the ground and that height are removed first: the robot's own body.
  std::size_t mark_ground(const Eigen::Vector3d& ground, std::uint64_t version,
                          std::optional<float> body_top = std::nullopt);
  /// The ground between last_driven_ and `ground`, footprints half a cell apart, if within driven_stride.
  std::size_t mark_way(const Eigen::Vector3d& ground, std::uint64_t version);
  /// The robot reached `ground`: the way there and its footprint are marked (mark_way, mark_ground) and it
  /// becomes last_driven_. What insert_scan and mark_passed share.
  std::size_t drive_to(const Eigen::Vector3d& ground, std::uint64_t version,
                       std::optional<float> body_top = std::nullopt);
  void trace_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& end, MlsInsertStats& stats);
  void merge_into(MlsTile& tile, MlsTile::Handle lower, MlsTile::Handle upper);

  MlsConfig config_;
  double inverse_resolution_;
  std::uint64_t version_ = 0;
  /// The ground point insert_scan last marked driven: the next one marks the way between (driven_stride).
  std::optional<Eigen::Vector3d> last_driven_;
  std::unordered_map<std::uint64_t, std::unique_ptr<MlsTile>, TileKeyHash> tiles_;
  // The last tile looked up: consecutive points of a scan almost always fall into the same tile.
  std::uint64_t cached_key_ = ~0ULL;
  MlsTile* cached_tile_ = nullptr;
};

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"
#include "core/points/point_cloud.hpp"
#include "server/encoding/tile_codec.hpp"
#include "server/state/map_state.hpp"

namespace strata::pipeline {

struct LiveMapOptions {
  MlsConfig mls;
  TraversabilityConfig traversability;
  encoding::TileCodecOptions codec;
};

/// Where one scan's mapping time went (docs/architecture.md 3, steps 6-8), milliseconds.
struct MappingTimes {
  double insert_ms = 0.0;    ///< step 6: points into the MLS map
  double drivable_ms = 0.0;  ///< step 7: classification and flood fill over the changed region
  double tiles_ms = 0.0;     ///< step 8: Draco for the changed tiles
  double png_ms = 0.0;       ///< step 8: the occupancy image
  double snapshot_ms = 0.0;  ///< step 8: the snapshot's tile list and map statistics
  std::size_t changed_tiles = 0;
  std::size_t region_cells = 0;
};

/// The map the server builds while the robot drives, and its wire form: the MLS map, the drivable map at
/// the robot's level over the last change, and the encoded tiles, of which only the changed ones are
/// re-encoded (unchanged tiles keep their shared encodings, so snapshots share them too). Not
/// thread-safe: the mapping worker owns it on its thread.
class LiveMap {
 public:
  explicit LiveMap(LiveMapOptions options = {});

  /// Step 6 for one registered scan: `points` in the map frame at full resolution, measured from
  /// `sensor_origin`; `robot_ground` the map-frame point the robot stands on; `received_at`: wall-clock
  /// time the scan reached the pipeline, stamped on what it changes. The scan joins the MLS map; the
  /// drivable map, the tiles and the snapshot (7-8) wait for
  /// refresh_pending(). A burst of scans then costs one refresh: with a lidar's far-reaching rays a
  /// refresh covers a scan's whole reach and cost 200 ms on the campus (issue 58), so refreshing after
  /// each of ten scans a second left most scans unmapped.
  MappingTimes insert_scan(const PointCloud& points, const Eigen::Vector3d& sensor_origin,
                           const Eigen::Vector3d& robot_ground, double received_at = 0.0);
  /// The robot passed `robot_ground` between two scans (one the mapping dropped): MlsMap::mark_passed, the
  /// change refreshed with the next scan's.
  void mark_passed(const Eigen::Vector3d& robot_ground);
  /// Steps 7-8 for every scan inserted since the last refresh; false (and nothing done) if there is none.
  bool refresh_pending(MappingTimes& times);

  /// Whether the robot localizes in this map (loaded for localizing: it does not change), for the
  /// snapshots from the next change on.
  void set_localizing(bool localizing) { localizing_ = localizing; }
  /// The saved map's name this one was loaded from or saved as, for the snapshots from the next one on.
  void set_name(std::string name) { name_ = std::move(name); }
  [[nodiscard]] const std::string& name() const { return name_; }
  /// The stored version (map server) of that name the map is; empty: none (changed since, or unversioned).
  void set_saved_version(std::string version) { saved_version_ = std::move(version); }
  [[nodiscard]] const std::string& saved_version() const { return saved_version_; }
  /// The snapshot again with the name and version set since (a save: the map itself is unchanged).
  void rename_snapshot();

  /// The robot moved on a map that is not changing (localizing in a loaded map): the drivable map at its
  /// level is computed again over the `radius` around it (a scan's reach), once it is `every` metres from
  /// where it was last computed. True when it was (there is something new to publish).
  bool follow_robot(const Eigen::Vector3d& robot_ground, double radius = 25.0, double every = 1.0);

  /// Replaces the map (a loaded file, a rebuild). Its version becomes newer than any before, and so do all
  /// its tiles, so clients that track versions redraw everything; tiles only the old map had become empty
  /// ones, so clients drop them. The drivable map is recomputed around the last known robot position over
  /// the whole new map.
  enum class Replacement {
    kLoaded,   ///< a map file
    kRebuilt,  ///< rebuilt from keyframes the pose graph moved (counted in MapSnapshot::rebuilds)
  };
  void replace(MlsMap map, Replacement why);

  [[nodiscard]] const MlsMap& map() const { return map_; }
  /// Null before the first scan or load.
  [[nodiscard]] const DrivableMap* drivable() const { return drivable_ ? &*drivable_ : nullptr; }
  [[nodiscard]] const std::optional<Eigen::Vector3d>& robot_ground() const { return robot_ground_; }

  /// The drivable map at the robot's level over the whole map (the ROS map download), of map `version`
  /// or, without one, the current map. Kept until one of a newer version is asked for, so that the YAML
  /// and the PGM of one version agree however far apart they are fetched.
  struct WholeLevel {
    std::shared_ptr<const DrivableMap> drivable;  ///< null: no robot position yet, or `gone`
    std::uint64_t version = 0;
    bool gone = false;  ///< `version` was asked for and is neither kept nor current
  };
  [[nodiscard]] WholeLevel whole_level(std::optional<std::uint64_t> version) const;
  /// The state to publish; a new object after every change.
  [[nodiscard]] std::shared_ptr<const MapSnapshot> snapshot() const { return snapshot_; }

 private:
  /// Steps 7 and 8 for `region` (changed tiles since `since`).
  void refresh(const CellRegion& region, std::uint64_t since, MappingTimes& times);

  LiveMapOptions options_;
  MlsMap map_;
  std::optional<DrivableMap> drivable_;
  std::optional<Eigen::Vector3d> robot_ground_;
  std::optional<Eigen::Vector3d> followed_from_;  ///< where follow_robot last computed the drivable map
  std::map<std::pair<int, int>, std::shared_ptr<const EncodedTile>> tiles_;  // sorted by (x, y)
  std::shared_ptr<const EncodedOccupancy> occupancy_;
  std::shared_ptr<const MapSnapshot> snapshot_;
  std::size_t rebuilds_ = 0;
  bool localizing_ = false;
  std::string name_;
  std::string saved_version_;
  mutable WholeLevel whole_level_;  ///< the last one made: a cache, so whole_level() stays const
  double received_at_ = 0.0;        // of the scan being added: stamped on the tiles and image it changes
  /// The map's version before the first scan inserted and not yet refreshed; none: nothing pending.
  std::optional<std::uint64_t> pending_since_;
};

}  // namespace strata::pipeline

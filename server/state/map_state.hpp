#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace strata {

/// One MLS tile encoded for the wire (proto/PROTOCOL.md, binary frame kind "tile"): a Draco point set,
/// one point per patch, quantized on the one global grid, with the patch attributes as Draco attributes.
/// Immutable once published; sessions share it.
struct EncodedTile {
  int tile_x = 0;  ///< tile index (cell index >> kMlsTileBits)
  int tile_y = 0;
  std::uint64_t version = 0;  ///< the map version that last changed the tile
  std::size_t patches = 0;
  std::vector<std::uint8_t> draco;  ///< empty when the tile holds no patches any more
  double stamp =
      0.0;  ///< wall-clock time (s since the epoch) the scan that last changed it was taken; 0: unknown
};

/// The drivable map at the robot's level as a PNG (free 254, occupied 0, unknown 205, as map_server).
struct EncodedOccupancy {
  std::uint64_t version = 0;  ///< the map version it was computed from
  double origin_x = 0.0;      ///< map-frame corner of the image's bottom-left cell, metres
  double origin_y = 0.0;
  double resolution = 0.1;  ///< metres per pixel
  int width = 0;
  int height = 0;
  double level_z = 0.0;           ///< ground height of the patch the robot stands on: which level this is
  std::vector<std::uint8_t> png;  ///< row 0 of the image is the highest y (image convention)
  double stamp = 0.0;  ///< wall-clock time (s since the epoch) of the scan it was computed after; 0: unknown
};

/// Everything a client needs to draw the map as it is now.
struct MapSnapshot {
  std::uint64_t version = 0;
  std::vector<std::shared_ptr<const EncodedTile>> tiles;  ///< every tile, sorted by (tile_x, tile_y)
  std::shared_ptr<const EncodedOccupancy> occupancy;      ///< null before the first drivable map
  std::size_t cells = 0;
  std::size_t patches = 0;
  std::size_t memory_bytes = 0;
  std::size_t rebuilds = 0;  ///< times the map was rebuilt from keyframes the pose graph moved
  /// The robot localizes in a loaded map that does not change; false: the scans go into the map.
  bool localizing = false;
  /// The saved map this one was loaded from or last saved as (a map store name); empty: never saved.
  std::string name;
  /// The map server's version of that name the map is (MapVersionInfo); empty: none (mapping changes it).
  std::string saved_version;
};

/// The newest map snapshot, written by the mapping worker, read by the network side. A shared_ptr swap
/// under a mutex: readers never wait for the mapping, and a snapshot outlives its replacement while sent.
class MapState {
 public:
  void publish(std::shared_ptr<const MapSnapshot> snapshot) {
    std::lock_guard lock(mutex_);
    latest_ = std::move(snapshot);
  }
  [[nodiscard]] std::shared_ptr<const MapSnapshot> snapshot() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const MapSnapshot> latest_;
};

}  // namespace strata

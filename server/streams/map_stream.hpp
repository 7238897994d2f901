#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "server/state/map_state.hpp"
#include "server/streams/outgoing_message.hpp"

namespace strata::streams {

/// Turns the mapping worker's snapshots into binary tile and occupancy frames for clients. Each frame is
/// encoded once and shared by every client. Frames carry a stream-wide sequence number as their order, not
/// the map version, so that loading an older map (lower versions) still replaces what clients hold.
class MapStream {
 public:
  explicit MapStream(const MapState& map) : map_(map) {}

  /// Frames for what changed since the last call: tiles whose version moved, tiles that are gone (an
  /// empty frame), the occupancy image if it is new. Called by the broadcast timer.
  [[nodiscard]] std::vector<streams::OutgoingMessage> poll();
  /// Every current frame, for a late joiner. Thread-safe.
  [[nodiscard]] std::vector<streams::OutgoingMessage> current() const;

  static std::string tile_key(int tile_x, int tile_y);

 private:
  const MapState& map_;
  mutable std::mutex mutex_;
  const MapSnapshot* last_ = nullptr;  // identity of the snapshot polled last (kept alive by last_hold_)
  std::shared_ptr<const MapSnapshot> last_hold_;
  double sequence_ = 0.0;
  struct TileFrame {
    std::shared_ptr<const EncodedTile> tile;  // unchanged tiles keep their pointer across snapshots
    streams::OutgoingMessage message;
  };
  std::map<std::pair<int, int>, TileFrame> tiles_;
  std::optional<streams::OutgoingMessage> occupancy_;
  const EncodedOccupancy* occupancy_identity_ = nullptr;
};

}  // namespace strata::streams

#include "server/streams/map_stream.hpp"

#include <string>

#include "server/protocol/binary_frames.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::streams {

std::string MapStream::tile_key(int tile_x, int tile_y) {
  return "tile:" + std::to_string(tile_x) + "," + std::to_string(tile_y);
}

std::vector<streams::OutgoingMessage> MapStream::poll() {
  const auto snapshot = map_.snapshot();
  std::lock_guard lock(mutex_);
  std::vector<streams::OutgoingMessage> changed;
  if (!snapshot || snapshot.get() == last_)
    return changed;
  const auto tiles_stream = static_cast<std::uint8_t>(protocol::Stream::kTiles);

  std::map<std::pair<int, int>, TileFrame> next;
  for (const auto& tile : snapshot->tiles) {
    const std::pair key{tile->tile_x, tile->tile_y};
    auto known = tiles_.find(key);
    if (known != tiles_.end() && known->second.tile == tile) {
      next.emplace(key, std::move(known->second));
      continue;
    }
    auto message = streams::OutgoingMessage::map_frame(
        protocol::encode_tile_frame(*tile), tile_key(tile->tile_x, tile->tile_y), ++sequence_, tiles_stream);
    changed.push_back(message);
    next.emplace(key, TileFrame{tile, std::move(message)});
  }
  // Tiles that are no longer in the map (a smaller map was loaded): an empty frame tells clients to drop
  // them.
  for (const auto& [key, frame] : tiles_) {
    if (next.contains(key))
      continue;
    EncodedTile gone{key.first, key.second, snapshot->version, 0, {}};
    changed.push_back(streams::OutgoingMessage::map_frame(
        protocol::encode_tile_frame(gone), tile_key(key.first, key.second), ++sequence_, tiles_stream));
  }
  tiles_ = std::move(next);

  if (snapshot->occupancy && snapshot->occupancy.get() != occupancy_identity_) {
    occupancy_identity_ = snapshot->occupancy.get();
    occupancy_ = streams::OutgoingMessage::map_frame(protocol::encode_occupancy_frame(*snapshot->occupancy),
                                                     "occupancy", ++sequence_,
                                                     static_cast<std::uint8_t>(protocol::Stream::kOccupancy));
    changed.push_back(*occupancy_);
  }
  last_ = snapshot.get();
  last_hold_ = snapshot;
  return changed;
}

std::vector<streams::OutgoingMessage> MapStream::current() const {
  std::lock_guard lock(mutex_);
  std::vector<streams::OutgoingMessage> frames;
  frames.reserve(tiles_.size() + 1);
  // The occupancy first: it is one frame and lets a client show the drivable map at once.
  if (occupancy_)
    frames.push_back(*occupancy_);
  for (const auto& [key, frame] : tiles_)
    frames.push_back(frame.message);
  return frames;
}

}  // namespace strata::streams

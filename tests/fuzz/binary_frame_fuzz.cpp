// Binary WebSocket frames: the tile and occupancy decoders (C++ clients, tests), and re-encoding what they
// accept must give a frame that decodes to the same thing.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "server/protocol/binary_frames.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> frame(data, size);
  if (const auto tile = strata::protocol::decode_tile_frame(frame)) {
    const std::string again = strata::protocol::encode_tile_frame(*tile);
    const auto decoded = strata::protocol::decode_tile_frame(
        {reinterpret_cast<const std::uint8_t*>(again.data()), again.size()});
    if (!decoded || decoded->draco != tile->draco || decoded->tile_x != tile->tile_x ||
        decoded->tile_y != tile->tile_y || decoded->version != tile->version)
      __builtin_trap();
  }
  if (const auto occupancy = strata::protocol::decode_occupancy_frame(frame)) {
    const std::string again = strata::protocol::encode_occupancy_frame(*occupancy);
    const auto decoded = strata::protocol::decode_occupancy_frame(
        {reinterpret_cast<const std::uint8_t*>(again.data()), again.size()});
    if (!decoded || decoded->png != occupancy->png || decoded->width != occupancy->width ||
        decoded->height != occupancy->height)
      __builtin_trap();
  }
  return 0;
}

#include "server/protocol/binary_frames.hpp"

#include <bit>
#include <cstring>
#include <type_traits>

namespace strata::protocol {
namespace {

static_assert(std::endian::native == std::endian::little,
              "binary frames are little-endian; a big-endian host needs byte swaps here");

template <typename T>
void put(std::string& out, std::size_t offset, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::memcpy(out.data() + offset, &value, sizeof(T));
}

template <typename T>
T get(std::span<const std::uint8_t> in, std::size_t offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  return value;
}

std::string header(FrameKind kind, std::size_t header_bytes, std::uint64_t version, double stamp,
                   std::size_t payload) {
  std::string out(header_bytes + payload, '\0');
  put(out, 0, static_cast<std::uint8_t>(kind));
  put(out, 1, kFrameLayoutVersion);
  put(out, 2, static_cast<std::uint16_t>(header_bytes));
  put(out, 8, version);
  put(out, 16, stamp);
  return out;
}

/// The payload offset of a frame of `kind` whose header holds at least `min_header` bytes, or 0.
std::size_t check_header(std::span<const std::uint8_t> frame, FrameKind kind, std::size_t min_header) {
  if (frame.size() < kCommonHeaderBytes || frame[0] != static_cast<std::uint8_t>(kind) ||
      frame[1] != kFrameLayoutVersion)
    return 0;
  const auto header_bytes = get<std::uint16_t>(frame, 2);
  if (header_bytes < min_header || header_bytes > frame.size())
    return 0;
  return header_bytes;
}

}  // namespace

std::string encode_tile_frame(const EncodedTile& tile) {
  std::string out = header(FrameKind::kTile, kTileHeaderBytes, tile.version, tile.stamp, tile.draco.size());
  put(out, 24, static_cast<std::int32_t>(tile.tile_x));
  put(out, 28, static_cast<std::int32_t>(tile.tile_y));
  put(out, 32, static_cast<std::uint32_t>(tile.patches));
  if (!tile.draco.empty())
    std::memcpy(out.data() + kTileHeaderBytes, tile.draco.data(), tile.draco.size());
  return out;
}

std::string encode_occupancy_frame(const EncodedOccupancy& occupancy) {
  std::string out = header(FrameKind::kOccupancy, kOccupancyHeaderBytes, occupancy.version, occupancy.stamp,
                           occupancy.png.size());
  put(out, 24, occupancy.origin_x);
  put(out, 32, occupancy.origin_y);
  put(out, 40, occupancy.resolution);
  put(out, 48, occupancy.level_z);
  put(out, 56, static_cast<std::uint32_t>(occupancy.width));
  put(out, 60, static_cast<std::uint32_t>(occupancy.height));
  if (!occupancy.png.empty())
    std::memcpy(out.data() + kOccupancyHeaderBytes, occupancy.png.data(), occupancy.png.size());
  return out;
}

std::optional<EncodedTile> decode_tile_frame(std::span<const std::uint8_t> frame) {
  const std::size_t payload = check_header(frame, FrameKind::kTile, kTileHeaderBytes);
  if (payload == 0)
    return std::nullopt;
  EncodedTile tile;
  tile.version = get<std::uint64_t>(frame, 8);
  tile.stamp = get<double>(frame, 16);
  tile.tile_x = get<std::int32_t>(frame, 24);
  tile.tile_y = get<std::int32_t>(frame, 28);
  tile.patches = get<std::uint32_t>(frame, 32);
  tile.draco.assign(frame.begin() + static_cast<std::ptrdiff_t>(payload), frame.end());
  return tile;
}

std::optional<EncodedOccupancy> decode_occupancy_frame(std::span<const std::uint8_t> frame) {
  const std::size_t payload = check_header(frame, FrameKind::kOccupancy, kOccupancyHeaderBytes);
  if (payload == 0)
    return std::nullopt;
  EncodedOccupancy occupancy;
  occupancy.version = get<std::uint64_t>(frame, 8);
  occupancy.stamp = get<double>(frame, 16);
  occupancy.origin_x = get<double>(frame, 24);
  occupancy.origin_y = get<double>(frame, 32);
  occupancy.resolution = get<double>(frame, 40);
  occupancy.level_z = get<double>(frame, 48);
  occupancy.width = static_cast<int>(get<std::uint32_t>(frame, 56));
  occupancy.height = static_cast<int>(get<std::uint32_t>(frame, 60));
  occupancy.png.assign(frame.begin() + static_cast<std::ptrdiff_t>(payload), frame.end());
  return occupancy;
}

}  // namespace strata::protocol

#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "server/state/map_state.hpp"

namespace strata::protocol {

/// Binary WebSocket frames (proto/PROTOCOL.md, "Binary frames"): a little-endian header, then the payload.
/// Common header, 24 bytes:
///   0  u8   kind            (FrameKind)
///   1  u8   layout version  (1)
///   2  u16  header_bytes    (the whole header, payload starts here; clients skip what they do not know)
///   4  u32  reserved        (0)
///   8  u64  version         (map version of the tile / occupancy)
///   16 f64  stamp           (wall-clock s since the epoch of the scan the data came from; 0 unknown)
/// Tile (kind 1), header_bytes 40:
///   24 i32  tile_x          32 u32  patches
///   28 i32  tile_y          36 u32  reserved (0)
///   payload: the Draco point set (proto/PROTOCOL.md "Tile payload"); empty: the tile is gone.
/// Occupancy (kind 2), header_bytes 64:
///   24 f64  origin_x        48 f64  level_z
///   32 f64  origin_y        56 u32  width
///   40 f64  resolution      60 u32  height
///   payload: PNG image, row 0 = highest y.
enum class FrameKind : std::uint8_t { kTile = 1, kOccupancy = 2 };

inline constexpr std::uint8_t kFrameLayoutVersion = 1;
inline constexpr std::size_t kCommonHeaderBytes = 24;
inline constexpr std::size_t kTileHeaderBytes = 40;
inline constexpr std::size_t kOccupancyHeaderBytes = 64;

[[nodiscard]] std::string encode_tile_frame(const EncodedTile& tile);
[[nodiscard]] std::string encode_occupancy_frame(const EncodedOccupancy& occupancy);

/// Decoders, for tests and C++ clients: nullopt when the frame is too short, of another kind or layout,
/// or its header length does not fit.
[[nodiscard]] std::optional<EncodedTile> decode_tile_frame(std::span<const std::uint8_t> frame);
[[nodiscard]] std::optional<EncodedOccupancy> decode_occupancy_frame(std::span<const std::uint8_t> frame);

}  // namespace strata::protocol

#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>

#include "core/mls/level_grid.hpp"
#include "server/state/map_state.hpp"

namespace strata::encoding {

/// Grey values of the occupancy image, as ROS map_server writes them.
inline constexpr std::uint8_t kPngFree = 254;
inline constexpr std::uint8_t kPngOccupied = 0;
inline constexpr std::uint8_t kPngUnknown = 205;

struct OccupancyPngError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The drivable map at one level as an 8-bit grey PNG (free 254, occupied 0, unknown 205; image row 0 is
/// the grid's highest y), with where it lies. `level_z` is the ground height the robot stands on.
[[nodiscard]] EncodedOccupancy encode_occupancy_png(const LevelGrid& grid, double level_z,
                                                    std::uint64_t version);

/// The grid back from encode_occupancy_png's PNG and placement (no surface heights). Throws
/// OccupancyPngError when the bytes are not such a PNG or its size disagrees with the placement.
[[nodiscard]] LevelGrid decode_occupancy_png(const EncodedOccupancy& encoded);

}  // namespace strata::encoding

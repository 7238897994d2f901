#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/mls/mls_map.hpp"
#include "core/mls/traversability.hpp"

namespace strata::encoding {

/// Draco tile payloads (proto/TILE_ENCODING.md): one point per patch, positions and depths quantized on
/// one global grid whose lines are the multiples of tile_grid_step(resolution), the same for every tile,
/// so neighbouring tiles meet without seams. The step divides the cell size by an even number, so cell
/// centres lie on grid lines (x and y are exact, and their deltas constant: 12 % smaller payloads than a
/// step of 1/128 m); it is at most kTileMaxGridStep, so no decoded coordinate is off by more than half
/// of it: 1/240 m = 4.17 mm at 0.1 m cells (the target is 5 mm).
inline constexpr double kTileMaxGridStep = 0.0085;
[[nodiscard]] double tile_grid_step(double resolution);

/// Draco attribute unique ids in a tile payload.
enum class TileAttribute : std::uint32_t {
  kPosition = 0,  ///< POSITION float32 x 3: cell centre x, y and the patch's top, metres, map frame
  kDepth = 1,     ///< GENERIC float32 x 1: 0 for a horizontal patch, else how far it reaches below its top
  kVariance = 2,  ///< GENERIC uint8 x 1: the top's variance, log-coded (variance_from_code)
  kClass = 3,     ///< GENERIC uint8 x 1: bit 0 vertical, bit 1 traversable
};
inline constexpr std::uint8_t kClassVertical = 1U;
inline constexpr std::uint8_t kClassTraversable = 2U;

/// Variance on a log scale in one byte, one code per octave: code = round(-log2(variance)), clamped to
/// [0, 255]; so 1 m^2 and above is 0. The decoded variance 2^-code is within a factor 2^(1/2) of the true
/// one, its standard deviation within 2^(1/4) (19 %): enough to colour patches by certainty. Finer codes
/// cost bytes: two per octave made campus tiles 8 % larger (tests/bench/map_encoding_bench.cpp).
[[nodiscard]] std::uint8_t variance_code(float variance);
[[nodiscard]] float variance_from_code(std::uint8_t code);

/// Draco's knobs that change the payload's size and the coding time.
struct TileCodecOptions {
  int encoding_speed = 5;  ///< 0 slowest and smallest .. 10 fastest
  int decoding_speed = 5;
  /// The kd-tree point coder (reorders points) instead of the sequential one, which codes each attribute
  /// as differences along the tile's row-major order; that suits a grid of patches better (measured:
  /// campus 35 % smaller, 3DTK about the same).
  bool kd_tree = false;
};

/// One decoded patch.
struct DecodedPatch {
  Eigen::Vector3f position;  ///< cell centre x, y; top z
  float depth = 0.0F;
  float variance = 0.0F;
  bool vertical = false;
  bool traversable = false;
};

/// A payload that is not a valid tile; what() says why.
struct TileCodecError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Encodes the patches of `tile` (at `index`, cells of `resolution` metres). `surfaces`, when given and
/// covering the tile, supplies the traversable flags; without it no patch is marked traversable. Empty
/// bytes for a tile without patches.
[[nodiscard]] std::vector<std::uint8_t> encode_tile(const MlsTile& tile, TileIndex index, double resolution,
                                                    const SurfaceGrid* surfaces = nullptr,
                                                    const TileCodecOptions& options = {});

/// Decodes a payload from encode_tile. The order of the patches is Draco's, not the tile's. Throws
/// TileCodecError on anything that is not a tile payload.
[[nodiscard]] std::vector<DecodedPatch> decode_tile(std::span<const std::uint8_t> payload);

}  // namespace strata::encoding

#include "server/encoding/tile_codec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

#include "drivers/io/threedtk_reader.hpp"

namespace strata::encoding {
namespace {

namespace fs = std::filesystem;

/// Every decoded patch lies within the bound of an original patch of its cell (position and depth), the
/// class and the variance code match it, and the counts agree.
void expect_round_trip(const MlsMap& map, TileIndex index, const std::vector<DecodedPatch>& decoded) {
  const double bound = tile_grid_step(map.resolution()) / 2.0 + 1e-5;  // float rounding at 100 m
  std::size_t originals = 0;
  const MlsTile& tile = *map.find_tile(index);
  for (int local = 0; local < kMlsTileCells; ++local)
    tile.for_each_patch(local, [&](const MlsPatch&) { ++originals; });
  ASSERT_EQ(decoded.size(), originals);
  for (const DecodedPatch& patch : decoded) {
    const CellIndex cell =
        map.cell_of(static_cast<double>(patch.position.x()), static_cast<double>(patch.position.y()));
    ASSERT_EQ(MlsMap::tile_of(cell), index) << "a patch outside its tile";
    const Eigen::Vector2d centre = map.cell_center(cell);
    EXPECT_NEAR(patch.position.x(), centre.x(), bound);
    EXPECT_NEAR(patch.position.y(), centre.y(), bound);
    const std::vector<MlsPatch> candidates = map.patches(cell);
    const MlsPatch* nearest = nullptr;
    for (const MlsPatch& original : candidates)
      if (nearest == nullptr ||
          std::abs(original.top() - patch.position.z()) < std::abs(nearest->top() - patch.position.z()))
        nearest = &original;
    ASSERT_NE(nearest, nullptr);
    EXPECT_NEAR(patch.position.z(), nearest->top(), bound);
    EXPECT_EQ(patch.vertical, nearest->vertical());
    if (nearest->vertical()) {
      EXPECT_NEAR(patch.depth, nearest->depth, bound);
    } else {
      EXPECT_EQ(patch.depth, 0.0F);
    }
    EXPECT_EQ(patch.variance, variance_from_code(variance_code(nearest->variance)));
  }
}

TEST(TileCodec, GridStepDividesTheCellAndKeepsTheErrorUnderFiveMillimetres) {
  for (const double resolution : {0.05, 0.1, 0.2, 0.25}) {
    const double step = tile_grid_step(resolution);
    EXPECT_LE(step / 2.0, 0.005) << resolution;
    const double steps_per_cell = resolution / step;
    EXPECT_NEAR(steps_per_cell, std::round(steps_per_cell), 1e-9) << resolution;
    EXPECT_EQ(static_cast<long>(std::round(steps_per_cell)) % 2, 0) << "cell centres on grid lines";
  }
  EXPECT_NEAR(tile_grid_step(0.1), 0.1 / 12.0, 1e-12);
}

TEST(TileCodec, VarianceCodeIsWithinHalfAnOctave) {
  for (const float variance : {1e-8F, 3e-6F, 1e-4F, 0.02F, 0.7F}) {
    const float decoded = variance_from_code(variance_code(variance));
    EXPECT_LE(std::abs(std::log2(decoded / variance)), 0.5F + 1e-6F) << variance;
  }
  EXPECT_EQ(variance_code(0.0F), 255);
  EXPECT_EQ(variance_code(std::numeric_limits<float>::quiet_NaN()), 255);
  EXPECT_EQ(variance_code(5.0F), 0);
}

TEST(TileCodec, HandMadeTilesRoundTripOnOneGridAcrossTheirBorder) {
  MlsMap map;
  // Two neighbouring tiles at negative indices: tile (-1, 0) and (0, 0) meet between cells x = -1 and 0.
  // Ramps across the border at heights that are no multiple of the step, a two-level cell (road and
  // bridge deck) and a wall.
  for (int y = 0; y < kMlsTileSize; ++y)
    for (int x = -kMlsTileSize; x < kMlsTileSize; ++x) {
      const float ground = 0.0137F * static_cast<float>(x) + 0.0031F * static_cast<float>(y) - 2.4F;
      ASSERT_TRUE(map.append_patch({x, y}, {ground, 1e-4F, 0.0F}));
      if (x == 3 && y < 10) {
        ASSERT_TRUE(map.append_patch({x, y}, {ground + 4.2F, 2e-5F, 0.0F}));  // a deck above the road
      }
      if (x == -5) {
        ASSERT_TRUE(map.append_patch({x, y}, {ground + 2.9F, 3e-3F, 1.873F}));  // a wall
      }
    }
  map.set_tile_version({-1, 0}, 1);
  map.set_tile_version({0, 0}, 1);
  const double step = tile_grid_step(map.resolution());
  for (const TileIndex index : {TileIndex{-1, 0}, TileIndex{0, 0}}) {
    const std::vector<std::uint8_t> payload = encode_tile(*map.find_tile(index), index, map.resolution());
    ASSERT_FALSE(payload.empty());
    const std::vector<DecodedPatch> decoded = decode_tile(payload);
    expect_round_trip(map, index, decoded);
    // Both tiles on the one global grid: every height a multiple of the step, so the tiles meet without
    // a seam.
    for (const DecodedPatch& patch : decoded) {
      const double steps = static_cast<double>(patch.position.z()) / step;
      EXPECT_NEAR(steps, std::round(steps), 1e-3);
    }
  }
}

TEST(TileCodec, MarksTraversablePatchesFromTheClassification) {
  MlsMap map;
  for (int y = 0; y < kMlsTileSize; ++y)
    for (int x = 0; x < kMlsTileSize; ++x)
      ASSERT_TRUE(map.append_patch({x, y}, {x < 16 ? 0.0F : 0.05F * static_cast<float>(x - 16), 1e-4F,
                                            0.0F}));  // flat, then 27 degrees
  const CellRegion region{{-2, -2}, kMlsTileSize + 4, kMlsTileSize + 4};
  const SurfaceGrid surfaces(map, region, TraversabilityConfig{});
  const std::vector<DecodedPatch> decoded =
      decode_tile(encode_tile(*map.find_tile({0, 0}), {0, 0}, map.resolution(), &surfaces));
  std::size_t flat = 0;
  std::size_t steep = 0;
  for (const DecodedPatch& patch : decoded) {
    if (patch.position.x() < 1.4F)
      flat += patch.traversable ? 1U : 0U;
    else if (patch.position.x() > 1.8F)
      steep += patch.traversable ? 1U : 0U;
  }
  EXPECT_GT(flat, 10U * 32U);
  EXPECT_EQ(steep, 0U);
}

TEST(TileCodec, NonFinitePatchesAreRefused) {
  MlsMap map;
  ASSERT_TRUE(map.append_patch({0, 0}, {std::numeric_limits<float>::infinity(), 1e-4F, 0.0F}));
  EXPECT_THROW(static_cast<void>(encode_tile(*map.find_tile({0, 0}), {0, 0}, map.resolution())),
               TileCodecError);
  MlsMap far;
  ASSERT_TRUE(far.append_patch({0, 0}, {0.0F, 1e-4F, 0.0F}));
  ASSERT_TRUE(far.append_patch({1, 0}, {1e8F, 1e-4F, 0.0F}));  // beyond Draco's 30 bits of grid steps
  EXPECT_THROW(static_cast<void>(encode_tile(*far.find_tile({0, 0}), {0, 0}, far.resolution())),
               TileCodecError);
}

TEST(TileCodec, EmptyTileEncodesToNothing) {
  const MlsTile tile;
  EXPECT_TRUE(encode_tile(tile, {0, 0}, 0.1).empty());
}

TEST(TileCodec, CorruptPayloadsGiveACleanError) {
  MlsMap map;
  for (int y = 0; y < kMlsTileSize; ++y)
    for (int x = 0; x < kMlsTileSize; ++x)
      ASSERT_TRUE(map.append_patch({x, y}, {0.01F * static_cast<float>(x * y), 1e-4F, 0.0F}));
  const std::vector<std::uint8_t> payload = encode_tile(*map.find_tile({0, 0}), {0, 0}, map.resolution());
  ASSERT_GT(payload.size(), 20U);

  EXPECT_THROW(static_cast<void>(decode_tile({})), TileCodecError);
  for (std::size_t length = 1; length < payload.size(); length += 7)
    EXPECT_THROW(static_cast<void>(decode_tile(std::span(payload).first(length))), TileCodecError) << length;
  std::mt19937 random(42);
  std::vector<std::uint8_t> garbage(payload.size());
  for (auto& byte : garbage)
    byte = static_cast<std::uint8_t>(random());
  EXPECT_THROW(static_cast<void>(decode_tile(garbage)), TileCodecError);
  // A flipped bit inside the entropy-coded body may still decode to some tile; it must never crash or
  // throw anything but TileCodecError (ASan watches the reads).
  for (std::size_t i = 0; i < payload.size(); i += 3) {
    std::vector<std::uint8_t> flipped = payload;
    flipped[i] ^= static_cast<std::uint8_t>(1U << (i % 8U));
    try {
      static_cast<void>(decode_tile(flipped));
    } catch (const TileCodecError&) {
    }
  }
}

TEST(TileCodec, RealTilesRoundTripWithinTheBound) {
  const fs::path dir = fs::path(STRATA_DATA_DIR) / "3dtk_dat";
  if (!fs::exists(dir / "scan000.3d") || !fs::exists(dir / "reference_slam6d_2009/scan000.frames"))
    GTEST_SKIP() << "no 3DTK scans in " << dir << " (set STRATA_DATA_DIR)";
  MlsMap map;
  for (int i = 0; i < 1; ++i) {  // one scan: enough tiles, and quick under ASan
    const std::string name = "scan00" + std::to_string(i);
    const Eigen::Isometry3d pose = io::read_3dtk_frames(dir / "reference_slam6d_2009" / (name + ".frames"));
    map.insert_scan(transformed(io::read_3dtk_scan(dir / (name + ".3d")).points, pose), pose.translation());
  }
  ASSERT_GT(map.tile_count(), 10U);
  std::size_t bytes = 0;
  for (const TileIndex& index : map.tile_indices()) {
    const std::vector<std::uint8_t> payload = encode_tile(*map.find_tile(index), index, map.resolution());
    bytes += payload.size();
    if (!payload.empty())
      expect_round_trip(map, index, decode_tile(payload));
  }
  EXPECT_LT(bytes, map.patch_count() * 12U) << "smaller than raw float xyz";
}

}  // namespace
}  // namespace strata::encoding

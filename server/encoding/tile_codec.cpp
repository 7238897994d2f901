#include "server/encoding/tile_codec.hpp"

#include <draco/compression/config/compression_shared.h>
#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>
#include <draco/point_cloud/point_cloud_builder.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

namespace strata::encoding {
namespace {

constexpr int kMaxQuantizationBits = 30;  // Draco's limit
constexpr float kMaxDepthRoundoff = 1e-4F;

struct PatchRow {
  std::array<float, 3> position;
  float depth;
  std::uint8_t variance;
  std::uint8_t klass;
};

/// Draco's explicit quantization on the global grid: the origin on a grid line at or below the smallest
/// value, the range (2^bits - 1) steps so that Draco's step, range / (2^bits - 1), is the grid's step.
struct GridQuantization {
  std::array<float, 3> origin{};
  int bits = 1;
  float range = 0.0F;
};

/// `dims` components of the position (first == 0) or the depth (first == 1).
GridQuantization grid_quantization(const std::vector<PatchRow>& rows, double step, int dims, int first) {
  GridQuantization q;
  double max_steps = 1.0;
  for (int d = 0; d < dims; ++d) {
    float low = std::numeric_limits<float>::infinity();
    float high = -std::numeric_limits<float>::infinity();
    for (const PatchRow& row : rows) {
      const float v = first == 0 ? row.position[static_cast<std::size_t>(d)] : row.depth;
      low = std::min(low, v);
      high = std::max(high, v);
    }
    const double origin_steps = std::floor(static_cast<double>(low) / step);
    q.origin[static_cast<std::size_t>(d)] = static_cast<float>(origin_steps * step);
    max_steps = std::max(max_steps, std::ceil(static_cast<double>(high) / step) - origin_steps);
  }
  if (!(max_steps < std::exp2(kMaxQuantizationBits)))  // also NaN
    throw TileCodecError("tile encoding: a tile spans more than 2^30 grid steps");
  q.bits = std::max(1, static_cast<int>(std::bit_width(static_cast<std::uint64_t>(max_steps))));
  q.range = static_cast<float>(static_cast<double>((std::uint64_t{1} << q.bits) - 1U) * step);
  return q;
}

std::vector<PatchRow> rows_of(const MlsTile& tile, TileIndex index, double resolution, double step,
                              const SurfaceGrid* surfaces) {
  std::vector<PatchRow> rows;
  rows.reserve(tile.pool.size());
  for (int local = 0; local < kMlsTileCells; ++local) {
    const CellIndex cell{index.x * kMlsTileSize + (local & (kMlsTileSize - 1)),
                         index.y * kMlsTileSize + (local >> kMlsTileBits)};
    const auto x = static_cast<float>((cell.x + 0.5) * resolution);
    const auto y = static_cast<float>((cell.y + 0.5) * resolution);
    std::span<const SurfaceGrid::Surface> classified;
    if (surfaces != nullptr && surfaces->region().contains(cell))
      classified = surfaces->surfaces(
          surfaces->cell(cell.x - surfaces->region().min.x, cell.y - surfaces->region().min.y));
    std::size_t i = 0;
    tile.for_each_patch(local, [&](const MlsPatch& patch) {
      std::uint8_t klass = patch.vertical() ? kClassVertical : 0U;
      if (i < classified.size() && classified[i].traversable)
        klass |= kClassTraversable;
      ++i;
      if (!std::isfinite(patch.top()) || !std::isfinite(patch.depth))
        throw TileCodecError("tile encoding: a patch with a non-finite height or depth");
      // A vertical patch stays vertical after rounding: its depth is at least one step.
      const float depth = patch.vertical() ? std::max(patch.depth, static_cast<float>(step)) : 0.0F;
      rows.push_back({{x, y, patch.top()}, depth, variance_code(patch.variance), klass});
    });
  }
  return rows;
}

}  // namespace

double tile_grid_step(double resolution) {
  const double halves = std::ceil(resolution / (2.0 * kTileMaxGridStep));
  return resolution / (2.0 * std::max(halves, 1.0));
}

std::uint8_t variance_code(float variance) {
  if (!(variance > 0.0F))  // zero, negative or NaN: as certain as the code can say
    return 255;
  const double code = std::round(-std::log2(static_cast<double>(variance)));
  return static_cast<std::uint8_t>(std::clamp(code, 0.0, 255.0));
}

float variance_from_code(std::uint8_t code) {
  return static_cast<float>(std::exp2(-static_cast<double>(code)));
}

std::vector<std::uint8_t> encode_tile(const MlsTile& tile, TileIndex index, double resolution,
                                      const SurfaceGrid* surfaces, const TileCodecOptions& options) {
  const double step = tile_grid_step(resolution);
  const std::vector<PatchRow> rows = rows_of(tile, index, resolution, step, surfaces);
  if (rows.empty())
    return {};
  const auto count = static_cast<draco::PointIndex::ValueType>(rows.size());

  draco::PointCloudBuilder builder;
  builder.Start(count);
  const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int depth = builder.AddAttribute(draco::GeometryAttribute::GENERIC, 1, draco::DT_FLOAT32);
  const int variance = builder.AddAttribute(draco::GeometryAttribute::GENERIC, 1, draco::DT_UINT8);
  const int klass = builder.AddAttribute(draco::GeometryAttribute::GENERIC, 1, draco::DT_UINT8);
  for (draco::PointIndex::ValueType i = 0; i < count; ++i) {
    const PatchRow& row = rows[i];
    builder.SetAttributeValueForPoint(position, draco::PointIndex(i), row.position.data());
    builder.SetAttributeValueForPoint(depth, draco::PointIndex(i), &row.depth);
    builder.SetAttributeValueForPoint(variance, draco::PointIndex(i), &row.variance);
    builder.SetAttributeValueForPoint(klass, draco::PointIndex(i), &row.klass);
  }
  std::unique_ptr<draco::PointCloud> cloud = builder.Finalize(false);
  if (!cloud)
    throw TileCodecError("tile encoding: Draco rejected the point set");
  cloud->attribute(position)->set_unique_id(static_cast<std::uint32_t>(TileAttribute::kPosition));
  cloud->attribute(depth)->set_unique_id(static_cast<std::uint32_t>(TileAttribute::kDepth));
  cloud->attribute(variance)->set_unique_id(static_cast<std::uint32_t>(TileAttribute::kVariance));
  cloud->attribute(klass)->set_unique_id(static_cast<std::uint32_t>(TileAttribute::kClass));

  draco::ExpertEncoder encoder(*cloud);
  encoder.SetSpeedOptions(options.encoding_speed, options.decoding_speed);
  encoder.SetEncodingMethod(options.kd_tree ? draco::POINT_CLOUD_KD_TREE_ENCODING
                                            : draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
  const GridQuantization positions = grid_quantization(rows, step, 3, 0);
  encoder.SetAttributeExplicitQuantization(position, positions.bits, 3, positions.origin.data(),
                                           positions.range);
  const GridQuantization depths = grid_quantization(rows, step, 1, 1);
  encoder.SetAttributeExplicitQuantization(depth, depths.bits, 1, depths.origin.data(), depths.range);
  // Depths are mostly zero with a few walls between: coding each value beats coding the difference to the
  // previous patch's, which turns every wall into two large residuals (3DTK tiles 5 % smaller, the campus
  // the same; tests/bench/map_encoding_bench.cpp).
  encoder.SetAttributePredictionScheme(depth, draco::PREDICTION_NONE);

  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeToBuffer(&buffer);
  if (!status.ok())
    throw TileCodecError("tile encoding: " + status.error_msg_string());
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(buffer.data());
  return {bytes, bytes + buffer.size()};
}

std::vector<DecodedPatch> decode_tile(std::span<const std::uint8_t> payload) {
  if (payload.empty())
    throw TileCodecError("tile payload: empty");
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(payload.data()), payload.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
  if (!decoded.ok())
    throw TileCodecError("tile payload: not a Draco point set: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::PointCloud> cloud = std::move(decoded).value();

  const auto attribute = [&](TileAttribute id, draco::DataType type, int components) {
    const draco::PointAttribute* a = cloud->GetAttributeByUniqueId(static_cast<std::uint32_t>(id));
    if (a == nullptr || a->data_type() != type || a->num_components() != components)
      throw TileCodecError("tile payload: attribute " + std::to_string(static_cast<int>(id)) +
                           " missing or of the wrong type");
    return a;
  };
  const draco::PointAttribute* position = attribute(TileAttribute::kPosition, draco::DT_FLOAT32, 3);
  const draco::PointAttribute* depth = attribute(TileAttribute::kDepth, draco::DT_FLOAT32, 1);
  const draco::PointAttribute* variance = attribute(TileAttribute::kVariance, draco::DT_UINT8, 1);
  const draco::PointAttribute* klass = attribute(TileAttribute::kClass, draco::DT_UINT8, 1);

  std::vector<DecodedPatch> patches(cloud->num_points());
  for (draco::PointIndex i(0); i < cloud->num_points(); ++i) {
    DecodedPatch& patch = patches[i.value()];
    std::array<float, 3> xyz{};
    std::array<float, 1> d{};
    std::array<std::uint8_t, 1> v{};
    std::array<std::uint8_t, 1> c{};
    if (!position->GetValue<float, 3>(position->mapped_index(i), &xyz) ||
        !depth->GetValue<float, 1>(depth->mapped_index(i), &d) ||
        !variance->GetValue<std::uint8_t, 1>(variance->mapped_index(i), &v) ||
        !klass->GetValue<std::uint8_t, 1>(klass->mapped_index(i), &c))
      throw TileCodecError("tile payload: attribute values out of range");
    // Dequantization may leave a zero depth a rounding error below zero.
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]) || !std::isfinite(d[0]) ||
        d[0] < -kMaxDepthRoundoff)
      throw TileCodecError("tile payload: a patch with a non-finite position or a negative depth");
    patch.position = {xyz[0], xyz[1], xyz[2]};
    patch.depth = std::max(d[0], 0.0F);
    patch.variance = variance_from_code(v[0]);
    patch.vertical = (c[0] & kClassVertical) != 0;
    patch.traversable = (c[0] & kClassTraversable) != 0;
  }
  return patches;
}

}  // namespace strata::encoding

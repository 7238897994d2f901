#include "drivers/lidar/ouster_decoder.hpp"

#include <cmath>
#include <numbers>

#include "drivers/lidar/byte_order.hpp"
#include "drivers/lidar/lidar_model.hpp"

namespace strata::lidar {
namespace {

constexpr std::size_t kBlocks = 16;
constexpr std::size_t kChannels = 64;
constexpr std::size_t kChannelSize = 12;
constexpr std::size_t kBlockHeader = 16;
constexpr std::size_t kBlockSize = kBlockHeader + kChannels * kChannelSize + 4;  // 788
constexpr std::uint32_t kEncoderTicks = 90112;
constexpr std::uint32_t kValidStatus = 0xffffffff;
constexpr std::uint32_t kRangeMask = 0x000fffff;

}  // namespace

OusterDecoder::OusterDecoder(const OusterMetadata& metadata)
    : columns_per_frame_(static_cast<std::uint32_t>(metadata.columns_per_frame)),
      beam_origin_mm_(static_cast<float>(metadata.lidar_origin_to_beam_origin_mm)),
      rotation_(metadata.lidar_to_sensor_transform.topLeftCorner<3, 3>().cast<float>()),
      translation_mm_(metadata.lidar_to_sensor_transform.topRightCorner<3, 1>().cast<float>()) {
  const std::vector<std::uint16_t> rings = rings_by_elevation(metadata.beam_altitude_angles);
  for (std::size_t i = 0; i < metadata.beam_altitude_angles.size(); ++i) {
    // The 1.x user guide's projection: a beam's azimuth offset turns against the encoder angle.
    const double azimuth = -metadata.beam_azimuth_angles[i] * std::numbers::pi / 180.0;
    const double altitude = metadata.beam_altitude_angles[i] * std::numbers::pi / 180.0;
    beams_.push_back(Beam{static_cast<float>(std::cos(azimuth)), static_cast<float>(std::sin(azimuth)),
                          static_cast<float>(std::cos(altitude)), static_cast<float>(std::sin(altitude)),
                          rings[i]});
  }
}

bool OusterDecoder::decode(std::span<const std::uint8_t> payload, double receive_stamp, DecodedPacket& out) {
  if (payload.size() != kPacketSize) {
    ++stats_.wrong_size;
    return false;
  }
  // The sensor's clock (boot time unless PTP-synchronised) anchors column times only relative to each
  // other; the last valid column is taken as the receive time.
  std::uint64_t last_stamp_ns = 0;
  std::size_t valid_blocks = 0;
  const auto block_valid = [&](const std::uint8_t* block) {
    return load_le<std::uint32_t>(block + kBlockSize - 4) == kValidStatus &&
           load_le<std::uint16_t>(block + 8) < columns_per_frame_ &&
           load_le<std::uint32_t>(block + 12) < kEncoderTicks;
  };
  for (std::size_t b = 0; b < kBlocks; ++b) {
    const std::uint8_t* block = payload.data() + b * kBlockSize;
    if (!block_valid(block))
      continue;
    ++valid_blocks;
    last_stamp_ns = std::max(last_stamp_ns, load_le<std::uint64_t>(block));
  }
  if (valid_blocks == 0) {
    ++stats_.no_valid_block;
    return false;
  }
  ++stats_.packets;
  stats_.invalid_blocks += kBlocks - valid_blocks;

  const std::size_t points_before = out.points.size();
  for (std::size_t b = 0; b < kBlocks; ++b) {
    const std::uint8_t* block = payload.data() + b * kBlockSize;
    if (!block_valid(block))
      continue;
    const std::uint64_t stamp_ns = load_le<std::uint64_t>(block);
    // A column stamped after the newest one cannot be; the difference is bounded by the check above.
    const double time = receive_stamp - static_cast<double>(last_stamp_ns - stamp_ns) * 1e-9;
    const std::uint16_t measurement_id = load_le<std::uint16_t>(block + 8);
    const std::uint32_t encoder = load_le<std::uint32_t>(block + 12);
    const double encoder_angle =
        2.0 * std::numbers::pi * (1.0 - static_cast<double>(encoder) / static_cast<double>(kEncoderTicks));
    const auto cos_encoder = static_cast<float>(std::cos(encoder_angle));
    const auto sin_encoder = static_cast<float>(std::sin(encoder_angle));
    LidarColumn column{time, static_cast<float>(measurement_id) / static_cast<float>(columns_per_frame_),
                       static_cast<std::uint32_t>(out.points.size()), 0,
                       static_cast<std::uint16_t>(kChannels)};
    const std::uint8_t* channel = block + kBlockHeader;
    for (std::size_t i = 0; i < kChannels; ++i, channel += kChannelSize) {
      const std::uint32_t range_mm = load_le<std::uint32_t>(channel) & kRangeMask;
      if (range_mm == 0)
        continue;  // no return
      const Beam& beam = beams_[i];
      const float along_beam = static_cast<float>(range_mm) - beam_origin_mm_;
      const float cos_angle = cos_encoder * beam.cos_azimuth - sin_encoder * beam.sin_azimuth;
      const float sin_angle = sin_encoder * beam.cos_azimuth + cos_encoder * beam.sin_azimuth;
      const Eigen::Vector3f in_lidar(
          along_beam * cos_angle * beam.cos_altitude + beam_origin_mm_ * cos_encoder,
          along_beam * sin_angle * beam.cos_altitude + beam_origin_mm_ * sin_encoder,
          along_beam * beam.sin_altitude);
      LidarPoint& point = out.points.emplace_back();
      point.position = (rotation_ * in_lidar + translation_mm_) * 1e-3f;
      point.intensity = static_cast<float>(load_le<std::uint16_t>(channel + 6));  // signal photons
      point.time = time;
      point.ring = beam.ring;
    }
    column.point_count = static_cast<std::uint32_t>(out.points.size() - column.first_point);
    out.columns.push_back(column);
  }
  stats_.returns += out.points.size() - points_before;
  stats_.rays += valid_blocks * kChannels;
  return true;
}

}  // namespace strata::lidar

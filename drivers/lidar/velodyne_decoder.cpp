#include "drivers/lidar/velodyne_decoder.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include "drivers/lidar/byte_order.hpp"
#include "drivers/lidar/lidar_config_error.hpp"

namespace strata::lidar {
namespace {

constexpr std::size_t kVelodyneBlocks = 12;
constexpr std::size_t kVelodyneBlockSize = 100;
constexpr std::size_t kChannelsPerBlock = 32;
constexpr std::uint16_t kUpperBlockFlag =
    0xeeff;                                     // stored ff ee; HDL-64's lower block 0xddff is foreign here
constexpr std::uint32_t kAzimuthUnits = 36000;  // 0.01 deg

constexpr std::uint8_t kReturnStrongest = 0x37;
constexpr std::uint8_t kReturnLast = 0x38;
constexpr std::uint8_t kProductHdl32e = 0x21;
constexpr std::uint8_t kProductVlp16 = 0x22;

// Firing schedules from the user manuals: VLP-16 fires 16 lasers 2.304 us apart, a sequence every
// 55.296 us, two sequences per block; HDL-32E fires its 32 lasers 1.152 us apart every 46.08 us, one
// sequence per block.
constexpr double kVlp16LaserInterval = 2.304e-6;
constexpr double kVlp16SequenceInterval = 55.296e-6;
constexpr double kHdl32eLaserInterval = 1.152e-6;
constexpr double kHdl32eSequenceInterval = 46.08e-6;

// More than this between consecutive blocks is a gap (invalid neighbour, dropped data), not rotation:
// at the fastest 20 Hz the VLP-16 turns 0.8 deg per block.
constexpr std::uint32_t kMaxAzimuthGap = 150;

struct AzimuthTable {
  std::vector<float> cos, sin;
};

const AzimuthTable& azimuth_table() {
  static const AzimuthTable table = [] {
    AzimuthTable made;
    made.cos.resize(kAzimuthUnits);
    made.sin.resize(kAzimuthUnits);
    for (std::uint32_t a = 0; a < kAzimuthUnits; ++a) {
      const double radians = static_cast<double>(a) * std::numbers::pi / 18000.0;
      made.cos[a] = static_cast<float>(std::cos(radians));
      made.sin[a] = static_cast<float>(std::sin(radians));
    }
    return made;
  }();
  return table;
}

}  // namespace

VelodyneDecoder::VelodyneDecoder(LidarModel model, const VelodyneCalibration& calibration) : model_(model) {
  if (model != LidarModel::kVlp16 && model != LidarModel::kHdl32e)
    throw LidarConfigError("the Velodyne decoder decodes vlp16 and hdl32e, not " + sensor_name(model));
  const std::size_t expected = model == LidarModel::kVlp16 ? 16 : 32;
  if (calibration.lasers.size() != expected)
    throw LidarConfigError("a " + sensor_name(model) + " has " + std::to_string(expected) +
                           " lasers but the calibration lists " + std::to_string(calibration.lasers.size()));
  distance_resolution_ = static_cast<float>(calibration.distance_resolution);
  std::vector<double> elevations;
  for (const VelodyneLaser& laser : calibration.lasers)
    elevations.push_back(laser.vert_correction);
  const std::vector<std::uint16_t> rings = rings_by_elevation(elevations);
  for (std::size_t i = 0; i < calibration.lasers.size(); ++i) {
    const VelodyneLaser& laser = calibration.lasers[i];
    lasers_.push_back(Laser{static_cast<float>(std::cos(laser.vert_correction)),
                            static_cast<float>(std::sin(laser.vert_correction)),
                            static_cast<float>(std::cos(laser.rot_correction)),
                            static_cast<float>(std::sin(laser.rot_correction)),
                            static_cast<float>(laser.dist_correction),
                            static_cast<float>(laser.vert_offset_correction),
                            static_cast<float>(laser.horiz_offset_correction), rings[i]});
  }
  cos_azimuth_ = azimuth_table().cos;
  sin_azimuth_ = azimuth_table().sin;
  last_azimuth_gap_ = model == LidarModel::kVlp16 ? 40 : 16;  // 10 Hz until the packets say otherwise
}

double VelodyneDecoder::packet_duration() const {
  return model_ == LidarModel::kVlp16 ? 2 * kVelodyneBlocks * kVlp16SequenceInterval
                                      : kVelodyneBlocks * kHdl32eSequenceInterval;
}

void VelodyneDecoder::add_return(const Laser& laser, std::uint32_t azimuth, const std::uint8_t* channel,
                                 double time, DecodedPacket& out) const {
  const std::uint16_t raw = load_le<std::uint16_t>(channel);
  if (raw == 0)
    return;  // no return
  const float distance = static_cast<float>(raw) * distance_resolution_ + laser.distance_offset;
  const float cos_a = cos_azimuth_[azimuth];
  const float sin_a = sin_azimuth_[azimuth];
  // The laser's azimuth is the block's minus its rotational correction.
  const float cos_angle = cos_a * laser.cos_rotation + sin_a * laser.sin_rotation;
  const float sin_angle = sin_a * laser.cos_rotation - cos_a * laser.sin_rotation;
  const float horizontal = distance * laser.cos_vertical - laser.vertical_offset * laser.sin_vertical;
  // Velodyne's azimuth turns clockwise seen from above, from the front: x forward, y left, z up.
  LidarPoint& point = out.points.emplace_back();
  point.position =
      Eigen::Vector3f(horizontal * cos_angle + laser.horizontal_offset * sin_angle,
                      -horizontal * sin_angle + laser.horizontal_offset * cos_angle,
                      distance * laser.sin_vertical + laser.vertical_offset * laser.cos_vertical);
  point.intensity = static_cast<float>(channel[2]);
  point.time = time;
  point.ring = laser.ring;
}

bool VelodyneDecoder::decode(std::span<const std::uint8_t> payload, double receive_stamp,
                             DecodedPacket& out) {
  if (payload.size() != kPacketSize) {
    ++stats_.wrong_size;
    return false;
  }
  const std::uint8_t return_mode = payload[1204];
  // Early firmware leaves the return-mode byte 0; dual return (0x39) interleaves two returns per azimuth.
  if (return_mode != kReturnStrongest && return_mode != kReturnLast && return_mode != 0) {
    ++stats_.unsupported_mode;
    return false;
  }
  std::array<std::uint32_t, kVelodyneBlocks> azimuths{};
  std::array<bool, kVelodyneBlocks> valid{};
  std::size_t valid_blocks = 0;
  for (std::size_t b = 0; b < kVelodyneBlocks; ++b) {
    const std::uint8_t* block = payload.data() + b * kVelodyneBlockSize;
    azimuths[b] = load_le<std::uint16_t>(block + 2);
    valid[b] = load_le<std::uint16_t>(block) == kUpperBlockFlag && azimuths[b] < kAzimuthUnits;
    valid_blocks += valid[b] ? 1 : 0;
  }
  if (valid_blocks == 0) {
    ++stats_.no_valid_block;
    return false;
  }
  ++stats_.packets;
  stats_.invalid_blocks += kVelodyneBlocks - valid_blocks;
  const std::uint8_t product = payload[1205];
  const std::uint8_t expected_product = model_ == LidarModel::kVlp16 ? kProductVlp16 : kProductHdl32e;
  if (product != expected_product)
    ++stats_.model_mismatch;

  const double first_firing = receive_stamp - packet_duration();
  const bool vlp16 = model_ == LidarModel::kVlp16;
  const std::size_t sequences = vlp16 ? 2 : 1;  // firing sequences per block
  const std::size_t lasers_per_sequence = kChannelsPerBlock / sequences;
  const double sequence_interval = vlp16 ? kVlp16SequenceInterval : kHdl32eSequenceInterval;
  const double laser_interval = vlp16 ? kVlp16LaserInterval : kHdl32eLaserInterval;
  const double block_duration = static_cast<double>(sequences) * sequence_interval;
  const std::size_t points_before = out.points.size();
  for (std::size_t b = 0; b < kVelodyneBlocks; ++b) {
    if (!valid[b])
      continue;
    const std::uint8_t* channels = payload.data() + b * kVelodyneBlockSize + 4;
    const std::uint32_t azimuth = azimuths[b];
    // The block's azimuth is its first firing's; the head keeps turning while the block's lasers fire, so
    // later firings are interpolated towards the next block's azimuth (the previous gap for the packet's
    // last block or an invalid neighbour).
    if (b + 1 < kVelodyneBlocks && valid[b + 1]) {
      const std::uint32_t gap = (azimuths[b + 1] + kAzimuthUnits - azimuth) % kAzimuthUnits;
      if (gap <= kMaxAzimuthGap)
        last_azimuth_gap_ = gap;
    }
    const double turn_per_second = static_cast<double>(last_azimuth_gap_) / block_duration;
    const auto azimuth_after = [&](double seconds) {
      return (azimuth + static_cast<std::uint32_t>(turn_per_second * seconds + 0.5)) % kAzimuthUnits;
    };
    const double block_time = first_firing + static_cast<double>(b) * block_duration;
    for (std::size_t sequence = 0; sequence < sequences; ++sequence) {
      const double sequence_offset = static_cast<double>(sequence) * sequence_interval;
      LidarColumn column{
          block_time + sequence_offset, static_cast<float>(azimuth_after(sequence_offset)) / 36000.0f,
          static_cast<std::uint32_t>(out.points.size()), 0, static_cast<std::uint16_t>(lasers_per_sequence)};
      for (std::size_t i = 0; i < lasers_per_sequence; ++i) {
        const double firing_offset = sequence_offset + static_cast<double>(i) * laser_interval;
        add_return(lasers_[i], azimuth_after(firing_offset),
                   channels + 3 * (lasers_per_sequence * sequence + i), block_time + firing_offset, out);
      }
      column.point_count = static_cast<std::uint32_t>(out.points.size() - column.first_point);
      out.columns.push_back(column);
    }
  }
  stats_.returns += out.points.size() - points_before;
  stats_.rays += valid_blocks * kChannelsPerBlock;
  return true;
}

}  // namespace strata::lidar

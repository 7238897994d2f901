#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "drivers/lidar/decoded_packet.hpp"
#include "drivers/lidar/ouster_metadata.hpp"

namespace strata::lidar {

/// Decodes legacy Ouster OS-1 (firmware 1.x) lidar packets: 16 azimuth blocks of {uint64 timestamp [ns],
/// uint16 measurement id, uint16 frame id, uint32 encoder count, 64 x {uint32 range [mm] (20 bits),
/// uint16 reflectivity, signal, noise, unused}, uint32 status}; a block counts only when its status is
/// 0xffffffff. Points are in the sensor frame (metadata's lidar_to_sensor_transform), metres.
class OusterDecoder {
 public:
  static constexpr std::size_t kPacketSize = 12608;

  explicit OusterDecoder(const OusterMetadata& metadata);

  /// Appends the columns and returns of one payload to `out`. Column times come from the sensor's own
  /// nanosecond stamps, placed so the packet's last valid column is at `receive_stamp` (s). Returns false,
  /// decoding nothing, when the payload is not a lidar packet with a valid block (counted in stats()).
  bool decode(std::span<const std::uint8_t> payload, double receive_stamp, DecodedPacket& out);

  [[nodiscard]] const DecodeStats& stats() const { return stats_; }

 private:
  struct Beam {
    float cos_azimuth, sin_azimuth, cos_altitude, sin_altitude;
    std::uint16_t ring;
  };
  std::vector<Beam> beams_;
  std::uint32_t columns_per_frame_;
  float beam_origin_mm_;
  Eigen::Matrix3f rotation_;
  Eigen::Vector3f translation_mm_;
  DecodeStats stats_;
};

}  // namespace strata::lidar

#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "drivers/lidar/decoded_packet.hpp"
#include "drivers/lidar/lidar_model.hpp"
#include "drivers/lidar/velodyne_calibration.hpp"

namespace strata::lidar {

/// Decodes Velodyne VLP-16 and HDL-32E data packets (UDP, 1206 bytes): 12 blocks of {0xEEFF flag, azimuth
/// [0.01 deg], 32 x (distance [resolution], intensity)}, a sensor timestamp, return mode and product bytes.
/// The model is the caller's: the product byte is only compared and a mismatch counted.
class VelodyneDecoder {
 public:
  static constexpr std::size_t kPacketSize = 1206;

  /// Throws LidarConfigError when `model` is not a Velodyne or the calibration's laser count does not fit
  /// it (16 for the VLP-16, 32 for the HDL-32E).
  VelodyneDecoder(LidarModel model, const VelodyneCalibration& calibration);

  /// Appends the columns and returns of one payload to `out`. `receive_stamp` is when the packet arrived
  /// (s); firing times are placed before it by the packet's own firing schedule. Returns false, decoding
  /// nothing, when the payload is not a single-return data packet (counted in stats()).
  bool decode(std::span<const std::uint8_t> payload, double receive_stamp, DecodedPacket& out);

  [[nodiscard]] const DecodeStats& stats() const { return stats_; }
  [[nodiscard]] LidarModel model() const { return model_; }
  /// Seconds the packet's firings span (VLP-16 24 x 55.296 us, HDL-32E 12 x 46.08 us).
  [[nodiscard]] double packet_duration() const;

 private:
  struct Laser {
    float cos_vertical, sin_vertical, cos_rotation, sin_rotation;
    float distance_offset, vertical_offset, horizontal_offset;
    std::uint16_t ring;
  };
  void add_return(const Laser& laser, std::uint32_t azimuth, const std::uint8_t* channel, double time,
                  DecodedPacket& out) const;

  LidarModel model_;
  std::vector<Laser> lasers_;
  float distance_resolution_;
  /// By azimuth in 0.01 deg (0..35999): the decoder's hot loop. One table for every decoder (made once),
  /// so that a decoder is cheap to make and to copy.
  std::span<const float> cos_azimuth_;
  std::span<const float> sin_azimuth_;
  std::uint32_t last_azimuth_gap_ = 0;  ///< 0.01 deg between blocks, for the packet's last block
  DecodeStats stats_;
};

}  // namespace strata::lidar

// Velodyne calibration files (strata serve --lidar vlp16|hdl32e --lidar-calibration FILE,
// velodyne_pointcloud's YAML). The parser either refuses the text (LidarConfigError) or returns lasers
// indexed by their ids with angles in range; a calibration the decoder then accepts must decode a packet to
// finite points, from the shortest range to the longest.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>

#include "decoded_packet_checks.hpp"
#include "drivers/lidar/lidar_config_error.hpp"
#include "drivers/lidar/velodyne_calibration.hpp"
#include "drivers/lidar/velodyne_decoder.hpp"

namespace {

using strata::lidar::VelodyneDecoder;

/// A data packet whose 12 blocks all fire, at azimuths around the turn, with the shortest and the longest
/// ranges a packet can carry on alternate channels.
std::array<std::uint8_t, VelodyneDecoder::kPacketSize> extreme_packet() {
  std::array<std::uint8_t, VelodyneDecoder::kPacketSize> packet{};
  for (std::size_t block = 0; block < 12; ++block) {
    std::uint8_t* at = packet.data() + block * 100;
    at[0] = 0xff;
    at[1] = 0xee;
    const auto azimuth = static_cast<std::uint16_t>(block * 2999);
    at[2] = static_cast<std::uint8_t>(azimuth & 0xff);
    at[3] = static_cast<std::uint8_t>(azimuth >> 8);
    for (std::size_t channel = 0; channel < 32; ++channel) {
      const std::uint16_t raw = channel % 2 == 0 ? 0xffff : 1;
      at[4 + 3 * channel] = static_cast<std::uint8_t>(raw & 0xff);
      at[5 + 3 * channel] = static_cast<std::uint8_t>(raw >> 8);
      at[6 + 3 * channel] = 255;
    }
  }
  packet[1204] = 0x37;  // strongest return
  return packet;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto packet = extreme_packet();
  strata::lidar::VelodyneCalibration calibration;
  try {
    calibration = strata::lidar::parse_velodyne_calibration(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
  } catch (const strata::lidar::LidarConfigError&) {
    return 0;
  }
  if (calibration.lasers.empty() ||
      !(calibration.distance_resolution > 0.0 && calibration.distance_resolution < 1.0))
    __builtin_trap();
  for (std::size_t i = 0; i < calibration.lasers.size(); ++i) {
    const auto& laser = calibration.lasers[i];
    if (laser.laser_id != static_cast<int>(i) || !(std::abs(laser.vert_correction) <= std::numbers::pi / 2))
      __builtin_trap();  // the lasers are in packet order, their elevations radians
  }
  const std::size_t lasers = calibration.lasers.size();
  if (lasers != 16 && lasers != 32)
    return 0;
  // The laser counts of the sensors the decoder knows (16: VLP-16, 32: HDL-32E).
  VelodyneDecoder decoder(
      lasers == 16 ? strata::lidar::LidarModel::kVlp16 : strata::lidar::LidarModel::kHdl32e, calibration);
  strata::lidar::DecodedPacket decoded;
  if (!decoder.decode(packet, 1000.0, decoded))
    __builtin_trap();
  strata::fuzz::check_decoded(decoded, 0, 0, lasers);
  return 0;
}

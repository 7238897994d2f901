// Ouster metadata files (strata serve --lidar os1 --lidar-calibration FILE: the sensor's beam intrinsics and
// mode as JSON). The parser either refuses the text (LidarConfigError: not JSON, nested too deep, a field
// missing or out of range) or returns 64 beams and a known mode; the decoder built from what it accepts must
// decode a packet to finite points, from the shortest range to the longest.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "decoded_packet_checks.hpp"
#include "drivers/lidar/lidar_config_error.hpp"
#include "drivers/lidar/ouster_decoder.hpp"
#include "drivers/lidar/ouster_metadata.hpp"

namespace {

using strata::lidar::OusterDecoder;

void put32(std::uint8_t* at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i)
    at[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

/// A lidar packet whose 16 columns are all valid (measurement ids 0..15, encoder counts around the turn),
/// with the shortest and the longest ranges a packet can carry on alternate channels.
std::vector<std::uint8_t> extreme_packet() {
  constexpr std::size_t kBlockSize = 16 + 64 * 12 + 4;
  std::vector<std::uint8_t> packet(OusterDecoder::kPacketSize, 0);
  for (std::size_t block = 0; block < 16; ++block) {
    std::uint8_t* at = packet.data() + block * kBlockSize;
    put32(at, static_cast<std::uint32_t>(1000 + block * 97656));  // ns
    at[8] = static_cast<std::uint8_t>(block);                     // measurement id
    put32(at + 12, static_cast<std::uint32_t>(block * 5631));     // encoder count, of 90112
    for (std::size_t channel = 0; channel < 64; ++channel)
      put32(at + 16 + channel * 12, channel % 2 == 0 ? 0x000fffff : 1);  // range, mm (20 bits)
    put32(at + kBlockSize - 4, 0xffffffff);                              // status: valid
  }
  return packet;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::uint8_t> packet = extreme_packet();
  strata::lidar::OusterMetadata metadata;
  try {
    metadata = strata::lidar::parse_ouster_metadata(std::string(reinterpret_cast<const char*>(data), size),
                                                    "fuzz.json");
  } catch (const strata::lidar::LidarConfigError&) {
    return 0;
  }
  if (metadata.beam_altitude_angles.size() != 64 || metadata.beam_azimuth_angles.size() != 64 ||
      !metadata.lidar_to_sensor_transform.allFinite() ||
      !std::isfinite(metadata.lidar_origin_to_beam_origin_mm))
    __builtin_trap();
  if (metadata.columns_per_frame != 512 && metadata.columns_per_frame != 1024 &&
      metadata.columns_per_frame != 2048)
    __builtin_trap();
  OusterDecoder decoder(metadata);
  strata::lidar::DecodedPacket decoded;
  if (!decoder.decode(packet, 1000.0, decoded))
    __builtin_trap();
  strata::fuzz::check_decoded(decoded, 0, 0, 64);
  return 0;
}

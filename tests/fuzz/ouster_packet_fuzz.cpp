// Ouster OS-1 (firmware 1.x) lidar packets (UDP from the sensor's network, or a capture's payloads) through
// the decoder and the revolution assembler, as LidarScanBuilder chains them. The input is cut into
// 12,608-byte payloads (a shorter rest is fed too: the decoder must count and skip it), decoded by a sensor
// in 1024x10 with every term of the projection in use: a beam origin offset and a lidar-to-sensor transform
// of its own (one sensor only: a packet of 1,024 returns takes a millisecond under the sanitizers).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "decoded_packet_checks.hpp"
#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/ouster_decoder.hpp"
#include "drivers/lidar/ouster_metadata.hpp"
#include "drivers/lidar/revolution_assembler.hpp"

namespace {

using strata::lidar::OusterDecoder;
using strata::lidar::OusterMetadata;

constexpr std::size_t kChannels = 64;

/// An OS-1-64's metadata as the sensor reports it (beams from +16.6 down to -16.6 degrees, staggered azimuth
/// offsets of about 3 degrees, 1024x10), with the newer firmware's beam origin offset and a transform of a
/// few degrees about x and y with a lever arm.
OusterMetadata metadata() {
  OusterMetadata metadata;
  for (std::size_t i = 0; i < kChannels; ++i) {
    metadata.beam_altitude_angles.push_back(16.6 - 33.2 * static_cast<double>(i) / (kChannels - 1));
    metadata.beam_azimuth_angles.push_back(i % 4 == 0 ? 3.1 : i % 4 == 1 ? 0.9 : i % 4 == 2 ? -1.2 : -3.0);
  }
  metadata.columns_per_frame = 1024;
  metadata.frequency = 10;
  metadata.lidar_origin_to_beam_origin_mm = 12.163;
  metadata.lidar_to_sensor_transform << 0.998, 0.0, 0.0523, 10.0, 0.0027, -0.9986, -0.0523, -5.0, 0.0522,
      0.0523, -0.9973, 40.0, 0, 0, 0, 1;
  return metadata;
}

void check_revolution(const strata::lidar::Revolution& revolution) {
  if (revolution.points.size() > revolution.rays || revolution.start > revolution.end)
    __builtin_trap();
  const strata::ScanEvent scan = strata::lidar::to_scan_event(revolution, "fuzz");
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!scan.points[i].allFinite() || !std::isfinite(scan.point_times[i]))
      __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const OusterMetadata sensor = metadata();
  const std::span<const std::uint8_t> input(data, size);
  OusterDecoder decoder(sensor);
  strata::lidar::RevolutionAssembler assembler;
  std::vector<strata::lidar::Revolution> revolutions;
  strata::lidar::DecodedPacket packet;
  double stamp = 1000.0;
  for (std::size_t offset = 0; offset < input.size(); offset += OusterDecoder::kPacketSize) {
    const auto payload = input.subspan(offset, std::min(OusterDecoder::kPacketSize, input.size() - offset));
    packet.clear();
    if (!decoder.decode(payload, stamp, packet)) {
      if (!packet.points.empty() || !packet.columns.empty())
        __builtin_trap();  // a refused payload decodes nothing
      continue;
    }
    strata::fuzz::check_decoded(packet, 0, 0, kChannels);
    assembler.add(packet, revolutions);
    stamp += 0.0016;
  }
  if (std::optional<strata::lidar::Revolution> partial = assembler.flush())
    revolutions.push_back(std::move(*partial));
  for (const auto& revolution : revolutions)
    check_revolution(revolution);
  if (decoder.stats().returns > decoder.stats().rays)
    __builtin_trap();
  return 0;
}

// Velodyne VLP-16 / HDL-32E data packets (UDP from the sensor's network, or a capture's payloads) through the
// decoder and the revolution assembler, as LidarScanBuilder chains them. The input is cut into 1206-byte
// payloads (a shorter rest is fed too: the decoder must count and skip it), decoded one packet duration apart
// by a VLP-16, an HDL-32E with the datasheet's angles and an HDL-32E with every correction of a calibration
// file set.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "decoded_packet_checks.hpp"
#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/revolution_assembler.hpp"
#include "drivers/lidar/velodyne_calibration.hpp"
#include "drivers/lidar/velodyne_decoder.hpp"

namespace {

using strata::lidar::LidarModel;
using strata::lidar::VelodyneDecoder;

/// The HDL-32E's nominal angles with the corrections a real calibration carries (centimetres, a few
/// milliradians), so that every term of the decoder's geometry is exercised.
strata::lidar::VelodyneCalibration corrected_hdl32e() {
  strata::lidar::VelodyneCalibration calibration = strata::lidar::nominal_hdl32e_calibration();
  for (std::size_t i = 0; i < calibration.lasers.size(); ++i) {
    auto& laser = calibration.lasers[i];
    const double sign = i % 2 == 0 ? 1.0 : -1.0;
    laser.rot_correction = sign * 0.004 * static_cast<double>(i % 5);
    laser.dist_correction = 0.01 * static_cast<double>(i % 7);
    laser.vert_offset_correction = 0.02 * sign;
    laser.horiz_offset_correction = -0.026 * sign;
  }
  calibration.distance_resolution = 0.004;
  return calibration;
}

void check_revolution(const strata::lidar::Revolution& revolution, std::size_t rings) {
  if (revolution.points.size() > revolution.rays || revolution.start > revolution.end)
    __builtin_trap();
  for (const auto& point : revolution.points) {
    if (!point.position.allFinite() || point.ring >= rings)
      __builtin_trap();
  }
  const strata::ScanEvent scan = strata::lidar::to_scan_event(revolution, "fuzz");
  for (const float time : scan.point_times) {
    if (!std::isfinite(time))
      __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  static const strata::lidar::VelodyneCalibration vlp16 = strata::lidar::nominal_vlp16_calibration();
  static const strata::lidar::VelodyneCalibration hdl32e = strata::lidar::nominal_hdl32e_calibration();
  static const strata::lidar::VelodyneCalibration corrected = corrected_hdl32e();
  for (VelodyneDecoder decoder :
       {VelodyneDecoder(LidarModel::kVlp16, vlp16), VelodyneDecoder(LidarModel::kHdl32e, hdl32e),
        VelodyneDecoder(LidarModel::kHdl32e, corrected)}) {
    const std::size_t rings = decoder.model() == LidarModel::kVlp16 ? 16 : 32;
    strata::lidar::RevolutionAssembler assembler;
    std::vector<strata::lidar::Revolution> revolutions;
    strata::lidar::DecodedPacket packet;
    double stamp = 1000.0;
    for (std::size_t offset = 0; offset < input.size(); offset += VelodyneDecoder::kPacketSize) {
      const auto payload =
          input.subspan(offset, std::min(VelodyneDecoder::kPacketSize, input.size() - offset));
      packet.clear();
      if (!decoder.decode(payload, stamp, packet)) {
        if (!packet.points.empty() || !packet.columns.empty())
          __builtin_trap();  // a refused payload decodes nothing
        continue;
      }
      strata::fuzz::check_decoded(packet, 0, 0, rings);
      assembler.add(packet, revolutions);
      stamp += decoder.packet_duration();
    }
    if (std::optional<strata::lidar::Revolution> partial = assembler.flush())
      revolutions.push_back(std::move(*partial));
    for (const auto& revolution : revolutions)
      check_revolution(revolution, rings);
    const auto& stats = decoder.stats();
    if (stats.returns > stats.rays)
      __builtin_trap();
  }
  return 0;
}

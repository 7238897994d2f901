#include "drivers/lidar/lidar_scan_builder.hpp"

#include "drivers/lidar/lidar_config_error.hpp"
#include "drivers/lidar/ouster_metadata.hpp"
#include "drivers/lidar/velodyne_calibration.hpp"

namespace strata::lidar {

std::variant<VelodyneDecoder, OusterDecoder> make_decoder(const LidarSetup& setup) {
  if (setup.model == LidarModel::kOs1) {
    if (setup.calibration.empty())
      throw LidarConfigError("an Ouster OS-1 needs its metadata JSON (--lidar-calibration)");
    return OusterDecoder(read_ouster_metadata(setup.calibration));
  }
  VelodyneCalibration calibration;
  if (!setup.calibration.empty())
    calibration = read_velodyne_calibration(setup.calibration);
  else
    calibration =
        setup.model == LidarModel::kVlp16 ? nominal_vlp16_calibration() : nominal_hdl32e_calibration();
  return VelodyneDecoder(setup.model, calibration);
}

ScanEvent to_scan_event(const Revolution& revolution, const std::string& sensor) {
  ScanEvent scan;
  scan.stamp = revolution.end;
  scan.duration = revolution.end - revolution.start;
  scan.sensor = sensor;
  scan.points.reserve(revolution.points.size());
  scan.point_times.reserve(revolution.points.size());
  for (const LidarPoint& point : revolution.points) {
    scan.points.push_back(point.position);
    scan.point_times.push_back(static_cast<float>(point.time - revolution.end));
  }
  scan.rays = revolution.rays;
  // Beams without a return are left out by the decoders rather than reported at a maximum range.
  scan.max_range = 0.0;
  return scan;
}

LidarScanBuilder::LidarScanBuilder(const LidarSetup& setup) : setup_(setup), decoder_(make_decoder(setup)) {
  if (setup_.port == 0)
    setup_.port = default_data_port(setup_.model);
}

const DecodeStats& LidarScanBuilder::decode_stats() const {
  return std::visit([](const auto& decoder) -> const DecodeStats& { return decoder.stats(); }, decoder_);
}

void LidarScanBuilder::add_datagram(std::uint16_t destination_port, std::span<const std::uint8_t> payload,
                                    double stamp, std::vector<ScanEvent>& scans) {
  if (destination_port != setup_.port) {
    ++stats_.wrong_port;
    return;
  }
  add_payload(payload, stamp, scans);
}

void LidarScanBuilder::add_payload(std::span<const std::uint8_t> payload, double stamp,
                                   std::vector<ScanEvent>& scans) {
  packet_.clear();
  const bool decoded =
      std::visit([&](auto& decoder) { return decoder.decode(payload, stamp, packet_); }, decoder_);
  if (!decoded)
    return;
  revolutions_.clear();
  assembler_.add(packet_, revolutions_);
  for (Revolution& revolution : revolutions_)
    emit(std::move(revolution), scans);
}

void LidarScanBuilder::finish(std::vector<ScanEvent>& scans) {
  if (std::optional<Revolution> partial = assembler_.flush())
    emit(std::move(*partial), scans);
}

void LidarScanBuilder::emit(Revolution&& revolution, std::vector<ScanEvent>& scans) {
  if (revolution.complete) {
    ++stats_.complete_revolutions;
  } else {
    ++stats_.partial_revolutions;
    if (!setup_.keep_partial)
      return;
  }
  const bool compensated =
      sensor_pose_at_ && compensate_motion(revolution.points, revolution.end, sensor_pose_at_);
  if (sensor_pose_at_ && !compensated)
    ++stats_.uncompensated_revolutions;
  scans.push_back(to_scan_event(revolution, sensor_name(setup_.model)));
  if (compensated)  // already as if measured at the end: nothing left to deskew
    scans.back().point_times.clear();
}

}  // namespace strata::lidar

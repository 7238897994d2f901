#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "drivers/lidar/decoded_packet.hpp"
#include "drivers/lidar/lidar_model.hpp"
#include "drivers/lidar/motion_compensation.hpp"
#include "drivers/lidar/ouster_decoder.hpp"
#include "drivers/lidar/revolution_assembler.hpp"
#include "drivers/lidar/velodyne_decoder.hpp"
#include "drivers/scan_event.hpp"

namespace strata::lidar {

/// Which sensor, and how to read it: what `strata serve --pcap FILE --lidar-model M --lidar-calibration F`
/// (or a live `--lidar-port`) describe.
struct LidarSetup {
  LidarModel model = LidarModel::kVlp16;
  /// Velodyne: velodyne_pointcloud calibration YAML (empty: the datasheet's nominal angles).
  /// Ouster: the sensor's metadata JSON (required).
  std::filesystem::path calibration;
  std::uint16_t port = 0;     ///< UDP destination port of the point data; 0: the model's default
  bool keep_partial = false;  ///< also hand on partial revolutions (stream start/end, dropped packets)
};

/// The sensor-independent part of the chain: UDP payloads of one lidar in, ScanEvents (one per
/// revolution, points in the sensor frame) out. Used by PcapScanSource and UdpPacketSource alike.
class LidarScanBuilder {
 public:
  /// Reads the calibration / metadata. Throws LidarConfigError.
  explicit LidarScanBuilder(const LidarSetup& setup);

  /// Compensates every revolution's motion with this pose source (sensor poses in a fixed frame) before
  /// it becomes a ScanEvent; revolutions it cannot cover are handed on uncompensated and counted.
  void set_motion_compensation(SensorPoseAt sensor_pose_at) { sensor_pose_at_ = std::move(sensor_pose_at); }

  /// Feeds one captured datagram: payloads for another port are skipped and counted.
  void add_datagram(std::uint16_t destination_port, std::span<const std::uint8_t> payload, double stamp,
                    std::vector<ScanEvent>& scans);
  /// Feeds one payload already known to be for this sensor (a socket bound to its port).
  void add_payload(std::span<const std::uint8_t> payload, double stamp, std::vector<ScanEvent>& scans);
  /// End of the stream: the revolution in progress, if partial ones are kept.
  void finish(std::vector<ScanEvent>& scans);

  struct Stats {
    std::size_t wrong_port = 0;
    std::size_t complete_revolutions = 0;
    std::size_t partial_revolutions = 0;        ///< handed on only if keep_partial
    std::size_t uncompensated_revolutions = 0;  ///< motion compensation asked for but odometry missing
  };
  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] const DecodeStats& decode_stats() const;
  [[nodiscard]] const LidarSetup& setup() const { return setup_; }

 private:
  void emit(Revolution&& revolution, std::vector<ScanEvent>& scans);

  LidarSetup setup_;
  std::variant<VelodyneDecoder, OusterDecoder> decoder_;
  RevolutionAssembler assembler_;
  DecodedPacket packet_;
  std::vector<Revolution> revolutions_;
  SensorPoseAt sensor_pose_at_;
  Stats stats_;
};

/// Makes the decoder a setup describes (reads its calibration). Throws LidarConfigError.
[[nodiscard]] std::variant<VelodyneDecoder, OusterDecoder> make_decoder(const LidarSetup& setup);

/// One revolution as the pipeline takes scans: stamp = its end, points in the sensor frame.
[[nodiscard]] ScanEvent to_scan_event(const Revolution& revolution, const std::string& sensor);

}  // namespace strata::lidar

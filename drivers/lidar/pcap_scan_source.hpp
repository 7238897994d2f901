#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/pcap_reader.hpp"

namespace strata::lidar {

/// A recorded lidar as a scan source: pcap file -> UDP datagrams -> decoder -> revolutions -> ScanEvents.
/// Scans come out in capture order with capture-clock stamps; pacing them to real time is the caller's.
class PcapScanSource {
 public:
  /// Opens the capture and reads the calibration. Throws PcapError or LidarConfigError.
  PcapScanSource(const std::filesystem::path& pcap, const LidarSetup& setup);

  /// The next scan, or nullopt when the capture is exhausted.
  [[nodiscard]] std::optional<ScanEvent> next();

  [[nodiscard]] LidarScanBuilder& builder() { return builder_; }
  [[nodiscard]] const LidarScanBuilder& builder() const { return builder_; }
  [[nodiscard]] const PcapStats& pcap_stats() const { return reader_.stats(); }

 private:
  PcapReader reader_;
  LidarScanBuilder builder_;
  std::vector<ScanEvent> ready_;
  std::size_t next_ready_ = 0;
  bool finished_ = false;
};

/// Every scan of a capture (complete revolutions; partial ones too if setup.keep_partial).
[[nodiscard]] std::vector<ScanEvent> read_pcap_scans(const std::filesystem::path& pcap,
                                                     const LidarSetup& setup);

}  // namespace strata::lidar

#include "drivers/lidar/pcap_scan_source.hpp"

namespace strata::lidar {

PcapScanSource::PcapScanSource(const std::filesystem::path& pcap, const LidarSetup& setup)
    : reader_(pcap), builder_(setup) {}

std::optional<ScanEvent> PcapScanSource::next() {
  while (next_ready_ == ready_.size()) {
    ready_.clear();
    next_ready_ = 0;
    if (finished_)
      return std::nullopt;
    if (const std::optional<UdpDatagram> datagram = reader_.next()) {
      builder_.add_datagram(datagram->destination_port, datagram->payload, datagram->stamp, ready_);
    } else {
      builder_.finish(ready_);
      finished_ = true;
    }
  }
  return std::move(ready_[next_ready_++]);
}

std::vector<ScanEvent> read_pcap_scans(const std::filesystem::path& pcap, const LidarSetup& setup) {
  PcapScanSource source(pcap, setup);
  std::vector<ScanEvent> scans;
  while (std::optional<ScanEvent> scan = source.next())
    scans.push_back(std::move(*scan));
  return scans;
}

}  // namespace strata::lidar

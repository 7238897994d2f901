#include "drivers/lidar/udp_scan_source.hpp"

namespace strata::lidar {

UdpScanSource::UdpScanSource(boost::asio::io_context& io, const LidarSetup& setup, const std::string& address,
                             std::optional<std::uint16_t> listen_port)
    : builder_(setup), packets_(io, listen_port.value_or(builder_.setup().port), address) {}

void UdpScanSource::start(ScanHandler handler) {
  handler_ = std::move(handler);
  packets_.start([this](std::span<const std::uint8_t> payload, double stamp) {
    builder_.add_payload(payload, stamp, ready_);
    hand_on();
  });
}

void UdpScanSource::stop() {
  packets_.stop();
  builder_.finish(ready_);
  hand_on();
}

void UdpScanSource::hand_on() {
  for (ScanEvent& scan : ready_)
    if (handler_)
      handler_(std::move(scan));
  ready_.clear();
}

}  // namespace strata::lidar

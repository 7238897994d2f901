#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <optional>
#include <string>

#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/udp_packet_source.hpp"

namespace strata::lidar {

/// A live lidar as a scan source: UDP datagrams on the setup's port (default: the model's) -> decoder ->
/// revolutions -> ScanEvents, handed on from the io_context's thread. Stamps are the host's receive
/// times (system clock), so odometry for motion compensation must be stamped on the same clock.
class UdpScanSource {
 public:
  using ScanHandler = std::function<void(ScanEvent&& scan)>;

  /// Reads the calibration and binds `address`:`listen_port` (nullopt: the setup's port; 0: any free
  /// port, see port()). Throws LidarConfigError or boost::system::system_error.
  UdpScanSource(boost::asio::io_context& io, const LidarSetup& setup, const std::string& address = "0.0.0.0",
                std::optional<std::uint16_t> listen_port = std::nullopt);

  void start(ScanHandler handler);
  /// Stops receiving and hands on the revolution in progress if partial ones are kept. Call on the
  /// io_context's thread (or after it stopped).
  void stop();

  [[nodiscard]] std::uint16_t port() const { return packets_.port(); }
  [[nodiscard]] std::size_t packets_received() const { return packets_.received(); }
  /// Decoder and assembly counters; read them on the io_context's thread.
  [[nodiscard]] LidarScanBuilder& builder() { return builder_; }

 private:
  void hand_on();

  LidarScanBuilder builder_;
  UdpPacketSource packets_;
  ScanHandler handler_;
  std::vector<ScanEvent> ready_;
};

}  // namespace strata::lidar

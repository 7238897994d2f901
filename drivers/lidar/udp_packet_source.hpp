#pragma once

#include <array>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace strata::lidar {

/// A live lidar's UDP stream: receives datagrams on a port (Velodyne 2368, Ouster 7502) on the caller's
/// io_context and hands each payload on with its receive time (system clock, s since the epoch).
/// Feed them to a LidarScanBuilder's add_payload.
class UdpPacketSource {
 public:
  using Handler = std::function<void(std::span<const std::uint8_t> payload, double receive_stamp)>;

  /// Binds `address`:`port` (port 0: any free port, see port()). Throws boost::system::system_error when
  /// the port cannot be bound. Asks for a large receive buffer: a sensor sends up to ~2 k packets/s in
  /// bursts and a busy pipeline must not make the kernel drop them.
  UdpPacketSource(boost::asio::io_context& io, std::uint16_t port, const std::string& address = "0.0.0.0");

  /// Starts receiving; `handler` runs on the io_context's thread for every datagram.
  void start(Handler handler);
  /// Stops receiving (closes the socket); call on the io_context's thread or after it stopped.
  void stop();

  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// Datagrams received so far; may be read from any thread.
  [[nodiscard]] std::size_t received() const { return received_.load(); }

 private:
  void receive();

  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint sender_;
  std::array<std::uint8_t, 65536> buffer_{};
  Handler handler_;
  std::uint16_t port_ = 0;
  std::atomic<std::size_t> received_{0};
};

}  // namespace strata::lidar

#include "drivers/lidar/udp_packet_source.hpp"

#include <boost/asio/socket_base.hpp>
#include <chrono>

namespace strata::lidar {

UdpPacketSource::UdpPacketSource(boost::asio::io_context& io, std::uint16_t port, const std::string& address)
    : socket_(io) {
  const boost::asio::ip::udp::endpoint endpoint(boost::asio::ip::make_address(address), port);
  socket_.open(endpoint.protocol());
  socket_.set_option(boost::asio::socket_base::reuse_address(true));
  boost::system::error_code ignored;  // the kernel caps it at net.core.rmem_max; a smaller buffer still works
  socket_.set_option(boost::asio::socket_base::receive_buffer_size(8 * 1024 * 1024), ignored);
  socket_.bind(endpoint);
  port_ = socket_.local_endpoint().port();
}

void UdpPacketSource::start(Handler handler) {
  handler_ = std::move(handler);
  receive();
}

void UdpPacketSource::stop() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

void UdpPacketSource::receive() {
  socket_.async_receive_from(
      boost::asio::buffer(buffer_), sender_,
      [this](const boost::system::error_code& error, std::size_t size) {
        if (error == boost::asio::error::operation_aborted || !socket_.is_open())
          return;
        if (!error) {
          ++received_;
          const double stamp =
              std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
          handler_(std::span<const std::uint8_t>(buffer_.data(), size), stamp);
        }
        receive();
      });
}

}  // namespace strata::lidar

#pragma once

#include <boost/asio/buffer.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "drivers/lidar/pcap_reader.hpp"

// Playing a capture's lidar packets to a live receiver over UDP: what the UdpPacketSource tests and the
// server's live-lidar integration test send.
namespace strata::lidar::test {

/// The payloads of the capture's UDP datagrams to `port` (the sensor's data port), in capture order.
inline std::vector<std::vector<std::uint8_t>> capture_payloads(const std::filesystem::path& pcap,
                                                               std::uint16_t port) {
  std::vector<std::vector<std::uint8_t>> payloads;
  PcapReader reader(pcap);
  while (const std::optional<UdpDatagram> datagram = reader.next()) {
    if (datagram->destination_port == port)
      payloads.emplace_back(datagram->payload.begin(), datagram->payload.end());
  }
  return payloads;
}

/// Sends `payloads` to `target` over UDP, one datagram each. After every `batch` datagrams (and once at
/// the end) calls `pace(sent so far)`, which may wait for the receiver to keep up: the kernel's receive
/// buffer is finite. Returns how many were sent.
inline std::size_t send_payloads(const std::vector<std::vector<std::uint8_t>>& payloads,
                                 const boost::asio::ip::udp::endpoint& target, std::size_t batch,
                                 const std::function<void(std::size_t)>& pace) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket sender(io, target.protocol());
  std::size_t sent = 0;
  for (const std::vector<std::uint8_t>& payload : payloads) {
    sender.send_to(boost::asio::buffer(payload.data(), payload.size()), target);
    ++sent;
    if (pace && sent % batch == 0)
      pace(sent);
  }
  if (pace)
    pace(sent);
  return sent;
}

}  // namespace strata::lidar::test

// Packet captures (strata serve --pcap FILE): the classic pcap reader over a capture in memory, every UDP
// datagram it finds (Ethernet with VLAN tags, Linux cooked capture, raw IPv4 frames). A capture holds
// whatever was on the wire: the reader either refuses the file header (PcapError) or reads to the end, and
// every payload it hands out lies inside the capture.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "drivers/lidar/pcap_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    strata::lidar::PcapReader reader(std::span<const std::uint8_t>(data, size));
    std::size_t datagrams = 0;
    while (const std::optional<strata::lidar::UdpDatagram> datagram = reader.next()) {
      ++datagrams;
      const std::uint8_t* begin = datagram->payload.data();
      if (!datagram->payload.empty() && (begin < data || begin + datagram->payload.size() > data + size))
        __builtin_trap();  // a payload is a view into the capture
      if (!std::isfinite(datagram->stamp) || datagram->stamp < 0.0)
        __builtin_trap();
    }
    const strata::lidar::PcapStats& stats = reader.stats();
    if (stats.datagrams != datagrams || stats.datagrams + stats.skipped() != stats.records)
      __builtin_trap();  // every record is a datagram or counted as skipped
  } catch (const strata::lidar::PcapError&) {
  }
  return 0;
}

#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

// The classic libpcap file format, read by hand rather than through libpcap: the format is a 24-byte
// file header and 16-byte record headers, libpcap would be a dependency for ~100 lines, and this reader
// must also parse in-memory buffers (the decode benchmark, the garbage-input tests) which libpcap's
// file-only offline API does not.
namespace strata::lidar {

/// A file that is not a pcap capture (bad magic, unsupported version or link type).
class PcapError : public std::runtime_error {
 public:
  explicit PcapError(const std::string& problem) : std::runtime_error(problem) {}
};

/// One UDP datagram from a capture. `payload` stays valid until the next call to PcapReader::next().
struct UdpDatagram {
  double stamp = 0.0;  ///< s since the Unix epoch, when the capture saw the frame
  std::uint16_t destination_port = 0;
  std::span<const std::uint8_t> payload;
};

/// What the reader skipped, and why. A capture holds whatever was on the wire; none of it is trusted.
struct PcapStats {
  std::size_t records = 0;     ///< frame records read
  std::size_t datagrams = 0;   ///< UDP datagrams returned
  std::size_t not_udp = 0;     ///< non-IPv4 / non-UDP frames (ARP, IPv6, TCP, ...)
  std::size_t fragmented = 0;  ///< IPv4 fragments (lidar packets fit one frame; fragments are skipped)
  std::size_t truncated_frames =
      0;                        ///< frames shorter than their own headers claim (snap length, corruption)
  bool truncated_file = false;  ///< the file ended inside a record (or a record claimed an absurd length)
  [[nodiscard]] std::size_t skipped() const { return not_udp + fragmented + truncated_frames; }
};

/// Where a UDP payload sits inside one captured link-layer frame; nullopt (and counted in `stats`) when
/// the frame is not a complete, unfragmented IPv4/UDP datagram.
struct UdpView {
  std::uint16_t destination_port = 0;
  std::span<const std::uint8_t> payload;
};
[[nodiscard]] std::optional<UdpView> find_udp_payload(std::uint32_t link_type,
                                                      std::span<const std::uint8_t> frame, PcapStats& stats);

/// Reads UDP datagrams from a classic pcap capture (either byte order, micro- or nanosecond timestamps;
/// link types Ethernet with optional 802.1Q VLAN tags, Linux cooked capture, raw IPv4). pcapng is not
/// supported (PcapError says so).
class PcapReader {
 public:
  /// Streams the file record by record (recordings can be far larger than memory). Throws PcapError.
  explicit PcapReader(const std::filesystem::path& path);
  /// Parses a capture already in memory; `bytes` must outlive the reader. Throws PcapError.
  explicit PcapReader(std::span<const std::uint8_t> bytes);

  /// The next UDP datagram, skipping (and counting) everything else; nullopt at the end of the capture.
  [[nodiscard]] std::optional<UdpDatagram> next();
  [[nodiscard]] const PcapStats& stats() const { return stats_; }
  [[nodiscard]] std::uint32_t link_type() const { return link_type_; }

 private:
  void read_file_header(const std::string& source);
  /// Points `out` at the next `size` bytes of the capture; false at its end.
  bool take(std::size_t size, std::span<const std::uint8_t>& out);

  std::ifstream file_;
  std::span<const std::uint8_t> memory_;
  bool from_memory_ = false;
  std::size_t memory_offset_ = 0;
  std::vector<std::uint8_t> buffer_;

  bool swapped_ = false;
  double fraction_unit_ = 1e-6;  ///< seconds per sub-second timestamp unit
  std::uint32_t link_type_ = 0;
  PcapStats stats_;
};

/// The whole file, for tests and benchmarks that parse captures from memory. Throws PcapError.
[[nodiscard]] std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);

}  // namespace strata::lidar

#include "drivers/lidar/pcap_reader.hpp"

#include <iterator>

#include "drivers/lidar/byte_order.hpp"

namespace strata::lidar {
namespace {

constexpr std::uint32_t kMagicMicroseconds = 0xa1b2c3d4;
constexpr std::uint32_t kMagicNanoseconds = 0xa1b23c4d;
constexpr std::uint32_t kPcapngMagic = 0x0a0d0d0a;
constexpr std::size_t kFileHeaderSize = 24;
constexpr std::size_t kRecordHeaderSize = 16;
// No link layer frame comes near this; a larger record length means a corrupt file, not a big packet.
constexpr std::uint32_t kMaxRecordSize = 256 * 1024;

constexpr std::uint32_t kLinkEthernet = 1;
constexpr std::uint32_t kLinkRawIp = 101;
constexpr std::uint32_t kLinkLinuxCooked = 113;

constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::uint16_t kEtherTypeQinQ = 0x88a8;
constexpr std::uint8_t kProtocolUdp = 17;

}  // namespace

std::optional<UdpView> find_udp_payload(std::uint32_t link_type, std::span<const std::uint8_t> frame,
                                        PcapStats& stats) {
  std::size_t offset = 0;
  std::uint16_t ether_type = kEtherTypeIpv4;
  if (link_type == kLinkEthernet) {
    if (frame.size() < 14) {
      ++stats.truncated_frames;
      return std::nullopt;
    }
    ether_type = load_be<std::uint16_t>(frame.data() + 12);
    offset = 14;
    while (ether_type == kEtherTypeVlan || ether_type == kEtherTypeQinQ) {
      if (frame.size() < offset + 4) {
        ++stats.truncated_frames;
        return std::nullopt;
      }
      ether_type = load_be<std::uint16_t>(frame.data() + offset + 2);
      offset += 4;
    }
  } else if (link_type == kLinkLinuxCooked) {
    if (frame.size() < 16) {
      ++stats.truncated_frames;
      return std::nullopt;
    }
    ether_type = load_be<std::uint16_t>(frame.data() + 14);
    offset = 16;
  }
  if (ether_type != kEtherTypeIpv4) {
    ++stats.not_udp;
    return std::nullopt;
  }

  const std::span<const std::uint8_t> ip = frame.subspan(offset);
  if (ip.size() < 20) {
    ++stats.truncated_frames;
    return std::nullopt;
  }
  const std::size_t header_length = std::size_t{ip[0] & 0x0fu} * 4;
  if ((ip[0] >> 4) != 4 || header_length < 20) {
    ++stats.not_udp;
    return std::nullopt;
  }
  if (ip[9] != kProtocolUdp) {
    ++stats.not_udp;
    return std::nullopt;
  }
  const std::uint16_t flags_and_offset = load_be<std::uint16_t>(ip.data() + 6);
  if ((flags_and_offset & 0x3fffu) != 0) {  // more-fragments flag or a fragment offset
    ++stats.fragmented;
    return std::nullopt;
  }
  const std::size_t total_length = load_be<std::uint16_t>(ip.data() + 2);
  if (total_length < header_length + 8 || total_length > ip.size()) {
    ++stats.truncated_frames;
    return std::nullopt;
  }
  const std::span<const std::uint8_t> udp = ip.subspan(header_length, total_length - header_length);
  const std::size_t udp_length = load_be<std::uint16_t>(udp.data() + 4);
  if (udp_length < 8 || udp_length > udp.size()) {
    ++stats.truncated_frames;
    return std::nullopt;
  }
  return UdpView{load_be<std::uint16_t>(udp.data() + 2), udp.subspan(8, udp_length - 8)};
}

PcapReader::PcapReader(const std::filesystem::path& path) : file_(path, std::ios::binary) {
  if (!file_)
    throw PcapError(path.string() + ": cannot open");
  read_file_header(path.string());
}

PcapReader::PcapReader(std::span<const std::uint8_t> bytes) : memory_(bytes), from_memory_(true) {
  read_file_header("pcap buffer");
}

bool PcapReader::take(std::size_t size, std::span<const std::uint8_t>& out) {
  if (from_memory_) {
    if (memory_.size() - memory_offset_ < size)
      return false;
    out = memory_.subspan(memory_offset_, size);
    memory_offset_ += size;
    return true;
  }
  buffer_.resize(size);
  file_.read(reinterpret_cast<char*>(buffer_.data()), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(file_.gcount()) != size)
    return false;
  out = buffer_;
  return true;
}

void PcapReader::read_file_header(const std::string& source) {
  std::span<const std::uint8_t> header;
  if (!take(kFileHeaderSize, header))
    throw PcapError(source + ": too short for a pcap file header");
  const std::uint32_t magic = load_le<std::uint32_t>(header.data());
  if (magic == kPcapngMagic)
    throw PcapError(source +
                    ": a pcapng file; only classic pcap is supported (convert with editcap -F pcap)");
  if (magic == kMagicMicroseconds || magic == kMagicNanoseconds) {
    swapped_ = false;
  } else if (byte_swapped(magic) == kMagicMicroseconds || byte_swapped(magic) == kMagicNanoseconds) {
    swapped_ = true;
  } else {
    throw PcapError(source + ": not a pcap file (unknown magic number)");
  }
  const std::uint32_t native_magic = swapped_ ? byte_swapped(magic) : magic;
  fraction_unit_ = native_magic == kMagicNanoseconds ? 1e-9 : 1e-6;
  const auto field16 = [&](std::size_t at) {
    const auto value = load_le<std::uint16_t>(header.data() + at);
    return swapped_ ? byte_swapped(value) : value;
  };
  if (field16(4) != 2)
    throw PcapError(source + ": unsupported pcap major version " + std::to_string(field16(4)));
  std::uint32_t link = load_le<std::uint32_t>(header.data() + 20);
  if (swapped_)
    link = byte_swapped(link);
  link_type_ = link & 0x0fffffffu;  // the top bits may carry an FCS length
  if (link_type_ != kLinkEthernet && link_type_ != kLinkRawIp && link_type_ != kLinkLinuxCooked)
    throw PcapError(source + ": unsupported link type " + std::to_string(link_type_) +
                    " (Ethernet, Linux cooked and raw IPv4 are supported)");
}

std::optional<UdpDatagram> PcapReader::next() {
  while (true) {
    std::span<const std::uint8_t> header;
    if (!take(kRecordHeaderSize, header)) {
      // A clean end leaves no bytes behind; anything else is a cut record header.
      if (from_memory_ ? memory_offset_ != memory_.size() : file_.gcount() != 0)
        stats_.truncated_file = true;
      return std::nullopt;
    }
    const auto field = [&](std::size_t at) {
      const auto value = load_le<std::uint32_t>(header.data() + at);
      return swapped_ ? byte_swapped(value) : value;
    };
    const double stamp = static_cast<double>(field(0)) + static_cast<double>(field(4)) * fraction_unit_;
    const std::uint32_t included = field(8);
    std::span<const std::uint8_t> frame;
    if (included > kMaxRecordSize || !take(included, frame)) {
      stats_.truncated_file = true;
      return std::nullopt;
    }
    ++stats_.records;
    if (const std::optional<UdpView> udp = find_udp_payload(link_type_, frame, stats_)) {
      ++stats_.datagrams;
      return UdpDatagram{stamp, udp->destination_port, udp->payload};
    }
  }
}

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw PcapError(path.string() + ": cannot open");
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

}  // namespace strata::lidar

#include "drivers/lidar/pcap_reader.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata::lidar {
namespace {

void put16(std::vector<std::uint8_t>& out, std::uint16_t value, bool big) {
  if (big) {
    out.push_back(static_cast<std::uint8_t>(value >> 8));
    out.push_back(static_cast<std::uint8_t>(value));
  } else {
    out.push_back(static_cast<std::uint8_t>(value));
    out.push_back(static_cast<std::uint8_t>(value >> 8));
  }
}
void put32(std::vector<std::uint8_t>& out, std::uint32_t value, bool big) {
  if (big) {
    put16(out, static_cast<std::uint16_t>(value >> 16), true);
    put16(out, static_cast<std::uint16_t>(value), true);
  } else {
    put16(out, static_cast<std::uint16_t>(value), false);
    put16(out, static_cast<std::uint16_t>(value >> 16), false);
  }
}

/// A capture written the way libpcap writes one, in either byte order.
struct CaptureWriter {
  bool big = false;
  std::vector<std::uint8_t> bytes;

  explicit CaptureWriter(bool big_endian, bool nanoseconds = false, std::uint32_t link = 1)
      : big(big_endian) {
    put32(bytes, nanoseconds ? 0xa1b23c4d : 0xa1b2c3d4, big);
    put16(bytes, 2, big);
    put16(bytes, 4, big);
    put32(bytes, 0, big);
    put32(bytes, 0, big);
    put32(bytes, 65535, big);
    put32(bytes, link, big);
  }
  void record(std::uint32_t seconds, std::uint32_t fraction, const std::vector<std::uint8_t>& frame) {
    put32(bytes, seconds, big);
    put32(bytes, fraction, big);
    put32(bytes, static_cast<std::uint32_t>(frame.size()), big);
    put32(bytes, static_cast<std::uint32_t>(frame.size()), big);
    bytes.insert(bytes.end(), frame.begin(), frame.end());
  }
};

/// An Ethernet / IPv4 / UDP frame (network byte order), optionally VLAN-tagged or with other protocol /
/// fragment fields.
std::vector<std::uint8_t> udp_frame(std::uint16_t port, const std::vector<std::uint8_t>& payload,
                                    bool vlan = false, std::uint8_t protocol = 17,
                                    std::uint16_t fragment = 0) {
  std::vector<std::uint8_t> frame(12, 0xab);  // MAC addresses
  if (vlan) {
    put16(frame, 0x8100, true);
    put16(frame, 7, true);
  }
  put16(frame, 0x0800, true);
  frame.push_back(0x45);
  frame.push_back(0);
  put16(frame, static_cast<std::uint16_t>(20 + 8 + payload.size()), true);
  put16(frame, 0, true);
  put16(frame, fragment, true);
  frame.push_back(64);
  frame.push_back(protocol);
  put16(frame, 0, true);
  put32(frame, 0xc0a80101, true);
  put32(frame, 0xffffffff, true);
  put16(frame, 40000, true);
  put16(frame, port, true);
  put16(frame, static_cast<std::uint16_t>(8 + payload.size()), true);
  put16(frame, 0, true);
  frame.insert(frame.end(), payload.begin(), payload.end());
  return frame;
}

TEST(PcapReader, ReadsBothByteOrdersAndTimestampResolutions) {
  for (const bool big : {false, true}) {
    for (const bool nanoseconds : {false, true}) {
      CaptureWriter capture(big, nanoseconds);
      capture.record(1000, nanoseconds ? 500000000 : 500000, udp_frame(2368, {1, 2, 3}));
      capture.record(1001, 0, udp_frame(7502, {9}, /*vlan=*/true));
      PcapReader reader{std::span<const std::uint8_t>(capture.bytes)};
      const std::optional<UdpDatagram> first = reader.next();
      ASSERT_TRUE(first) << "big-endian " << big << " ns " << nanoseconds;
      EXPECT_DOUBLE_EQ(first->stamp, 1000.5);
      EXPECT_EQ(first->destination_port, 2368);
      EXPECT_EQ(std::vector<std::uint8_t>(first->payload.begin(), first->payload.end()),
                (std::vector<std::uint8_t>{1, 2, 3}));
      const std::optional<UdpDatagram> second = reader.next();
      ASSERT_TRUE(second);
      EXPECT_EQ(second->destination_port, 7502);
      EXPECT_EQ(second->payload.size(), 1u);
      EXPECT_FALSE(reader.next());
      EXPECT_FALSE(reader.stats().truncated_file);
      EXPECT_EQ(reader.stats().datagrams, 2u);
    }
  }
}

TEST(PcapReader, SkipsAndCountsNonUdpFragmentedAndTruncatedFrames) {
  CaptureWriter capture(false);
  std::vector<std::uint8_t> arp(12, 0xff);
  put16(arp, 0x0806, true);
  arp.resize(42, 0);
  capture.record(1, 0, arp);
  capture.record(2, 0, udp_frame(2368, {1, 2}, false, /*protocol TCP*/ 6));
  capture.record(3, 0, udp_frame(2368, {1, 2}, false, 17, /*more fragments*/ 0x2000));
  std::vector<std::uint8_t> cut = udp_frame(2368, std::vector<std::uint8_t>(100, 7));
  cut.resize(60);  // snap length: IP says 128 bytes, 46 arrived
  capture.record(4, 0, cut);
  capture.record(5, 0, {0x01, 0x02});  // not even an Ethernet header
  capture.record(6, 0, udp_frame(2368, {42}));
  PcapReader reader{std::span<const std::uint8_t>(capture.bytes)};
  const std::optional<UdpDatagram> only = reader.next();
  ASSERT_TRUE(only);
  EXPECT_EQ(only->payload[0], 42);
  EXPECT_FALSE(reader.next());
  EXPECT_EQ(reader.stats().records, 6u);
  EXPECT_EQ(reader.stats().not_udp, 2u);
  EXPECT_EQ(reader.stats().fragmented, 1u);
  EXPECT_EQ(reader.stats().truncated_frames, 2u);
  EXPECT_EQ(reader.stats().skipped(), 5u);
}

TEST(PcapReader, AFileCutInsideARecordEndsCleanlyAndSaysSo) {
  CaptureWriter capture(false);
  capture.record(1, 0, udp_frame(2368, std::vector<std::uint8_t>(1206, 1)));
  capture.record(2, 0, udp_frame(2368, std::vector<std::uint8_t>(1206, 2)));
  for (const std::size_t cut :
       {capture.bytes.size() - 1, capture.bytes.size() - 700, capture.bytes.size() - 1250}) {
    const std::vector<std::uint8_t> truncated(capture.bytes.begin(),
                                              capture.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    PcapReader reader{std::span<const std::uint8_t>(truncated)};
    std::size_t datagrams = 0;
    while (reader.next())
      ++datagrams;
    EXPECT_EQ(datagrams, 1u) << "cut at " << cut;
    EXPECT_TRUE(reader.stats().truncated_file) << "cut at " << cut;
  }
}

TEST(PcapReader, RejectsWhatIsNotAClassicPcapWithAClearError) {
  const std::vector<std::uint8_t> short_file(10, 0);
  EXPECT_THROW(PcapReader{std::span<const std::uint8_t>(short_file)}, PcapError);
  std::vector<std::uint8_t> pcapng = {0x0a, 0x0d, 0x0d, 0x0a};
  pcapng.resize(64, 0);
  try {
    PcapReader reader{std::span<const std::uint8_t>(pcapng)};
    FAIL() << "pcapng accepted";
  } catch (const PcapError& error) {
    EXPECT_NE(std::string(error.what()).find("pcapng"), std::string::npos) << error.what();
  }
  CaptureWriter wifi(false, false, /*IEEE 802.11*/ 105);
  EXPECT_THROW(PcapReader{std::span<const std::uint8_t>(wifi.bytes)}, PcapError);
  EXPECT_THROW(PcapReader{std::filesystem::path("/nonexistent/capture.pcap")}, PcapError);
}

TEST(PcapReader, RandomBytesAfterAValidHeaderNeverCrash) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 200; ++trial) {
    CaptureWriter capture(trial % 2 == 0);
    const std::size_t size = random() % 4000;
    for (std::size_t i = 0; i < size; ++i)
      capture.bytes.push_back(static_cast<std::uint8_t>(random()));
    PcapReader reader{std::span<const std::uint8_t>(capture.bytes)};
    std::size_t payload_bytes = 0;
    while (const std::optional<UdpDatagram> datagram = reader.next())
      payload_bytes += datagram->payload.size();
    EXPECT_LE(payload_bytes, capture.bytes.size());
  }
}

TEST(PcapReader, RealCapturesHoldTheirDocumentedPackets) {
  const std::filesystem::path file = test::lidar_data_dir() / "hdl32_example.pcap";
  STRATA_SKIP_WITHOUT(file);
  // Streamed from the file and parsed from memory: the same datagrams.
  PcapReader streamed(file);
  const std::vector<std::uint8_t> bytes = read_file_bytes(file);
  PcapReader in_memory{std::span<const std::uint8_t>(bytes)};
  std::size_t data = 0;
  std::size_t position = 0;
  while (const std::optional<UdpDatagram> datagram = streamed.next()) {
    const std::optional<UdpDatagram> same = in_memory.next();
    ASSERT_TRUE(same);
    EXPECT_EQ(same->stamp, datagram->stamp);
    EXPECT_EQ(same->payload.size(), datagram->payload.size());
    if (datagram->destination_port == 2368 && datagram->payload.size() == 1206)
      ++data;
    if (datagram->destination_port == 8308 && datagram->payload.size() == 512)
      ++position;
  }
  EXPECT_FALSE(in_memory.next());
  EXPECT_EQ(streamed.stats().records, 976u);
  EXPECT_EQ(data, 876u);
  EXPECT_EQ(position, 100u);
  EXPECT_EQ(streamed.stats().skipped(), 0u);
  EXPECT_FALSE(streamed.stats().truncated_file);
}

}  // namespace
}  // namespace strata::lidar

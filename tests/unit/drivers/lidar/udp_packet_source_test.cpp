#include "drivers/lidar/udp_packet_source.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <thread>

#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/pcap_reader.hpp"
#include "drivers/lidar/udp_scan_source.hpp"
#include "tests/unit/drivers/lidar/lidar_loopback.hpp"
#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata::lidar {
namespace {

using namespace std::chrono_literals;

/// Sends a capture's lidar payloads over loopback UDP to a live UdpScanSource (a UdpPacketSource feeding
/// a LidarScanBuilder), and returns the scans it built. Sending waits for the receiver to keep up (the
/// kernel's receive buffer is finite), so no packet is lost however slow the machine.
struct LoopbackRun {
  std::vector<ScanEvent> scans;
  std::size_t sent = 0;
  std::size_t received = 0;
  DecodeStats decode;
  LidarScanBuilder::Stats builder;
};

LoopbackRun send_over_loopback(const std::filesystem::path& pcap, const LidarSetup& setup) {
  boost::asio::io_context io;
  UdpScanSource source(io, setup, "127.0.0.1", /*listen_port=*/0);
  LoopbackRun run;
  source.start([&run](ScanEvent&& scan) { run.scans.push_back(std::move(scan)); });
  std::thread receiver([&io] { io.run(); });

  const auto wait_for = [&](std::size_t count) {
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (source.packets_received() < count && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(1ms);
  };
  run.sent = test::send_payloads(
      test::capture_payloads(pcap, default_data_port(setup.model)),
      boost::asio::ip::udp::endpoint(boost::asio::ip::make_address("127.0.0.1"), source.port()), 32,
      wait_for);
  boost::asio::post(io, [&source] { source.stop(); });
  receiver.join();
  run.received = source.packets_received();
  run.decode = source.builder().decode_stats();
  run.builder = source.builder().stats();
  return run;
}

TEST(UdpPacketSource, ReceivesAVelodyneStreamOverLoopbackAndBuildsItsRevolutions) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "hdl32_example.pcap");
  const LoopbackRun run =
      send_over_loopback(dir / "hdl32_example.pcap", LidarSetup{LidarModel::kHdl32e, dir / "32db.yaml"});
  EXPECT_EQ(run.sent, 876u);
  EXPECT_EQ(run.received, 876u);
  EXPECT_EQ(run.decode.packets, 876u);
  EXPECT_EQ(run.builder.complete_revolutions, 5u);
  ASSERT_EQ(run.scans.size(), 5u);
  for (const ScanEvent& scan : run.scans) {
    EXPECT_GT(scan.points.size(), 42000u);
    EXPECT_LT(scan.points.size(), 46000u);
  }
}

TEST(UdpPacketSource, ReceivesAnOusterStreamOverLoopback) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "ouster_example.pcap");
  const LoopbackRun run = send_over_loopback(dir / "ouster_example.pcap",
                                             LidarSetup{LidarModel::kOs1, dir / "ouster_example.json"});
  EXPECT_EQ(run.received, 100u);
  EXPECT_EQ(run.decode.packets, 100u);
  ASSERT_EQ(run.scans.size(), 1u);
  EXPECT_EQ(run.scans[0].rays, 1024u * 64u);
}

TEST(UdpPacketSource, AnAddressItCannotBindIsAClearError) {
  boost::asio::io_context io;
  EXPECT_THROW(UdpPacketSource(io, 0, "192.0.2.1"), boost::system::system_error);
  EXPECT_THROW(UdpPacketSource(io, 0, "not-an-address"), boost::system::system_error);
}

}  // namespace
}  // namespace strata::lidar

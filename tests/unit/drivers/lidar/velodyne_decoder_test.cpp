#include "drivers/lidar/velodyne_decoder.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <random>

#include "drivers/lidar/lidar_config_error.hpp"
#include "drivers/lidar/pcap_reader.hpp"
#include "drivers/lidar/pcap_scan_source.hpp"
#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata::lidar {
namespace {

/// A VLP-16 / HDL-32E data packet with every block valid at `azimuth` + 0.4 deg steps and no returns.
std::vector<std::uint8_t> empty_packet(std::uint16_t azimuth, std::uint8_t product) {
  std::vector<std::uint8_t> packet(VelodyneDecoder::kPacketSize, 0);
  for (std::size_t b = 0; b < 12; ++b) {
    std::uint8_t* block = packet.data() + b * 100;
    block[0] = 0xff;
    block[1] = 0xee;
    const auto value = static_cast<std::uint16_t>((azimuth + 40 * b) % 36000);
    block[2] = static_cast<std::uint8_t>(value);
    block[3] = static_cast<std::uint8_t>(value >> 8);
  }
  packet[1204] = 0x37;
  packet[1205] = product;
  return packet;
}

void set_return(std::vector<std::uint8_t>& packet, std::size_t block, std::size_t channel, double metres) {
  const auto raw = static_cast<std::uint16_t>(std::lround(metres / 0.002));
  std::uint8_t* at = packet.data() + block * 100 + 4 + 3 * channel;
  at[0] = static_cast<std::uint8_t>(raw);
  at[1] = static_cast<std::uint8_t>(raw >> 8);
  at[2] = 99;
}

TEST(VelodyneDecoder, PlacesAReturnInTheSensorFrameXForwardYLeftZUp) {
  VelodyneDecoder decoder(LidarModel::kVlp16, nominal_vlp16_calibration());
  std::vector<std::uint8_t> packet = empty_packet(9000, 0x22);  // block 0 at azimuth 90 deg: to the right
  set_return(packet, 0, 0, 10.0);                               // laser 0: -15 deg
  DecodedPacket out;
  ASSERT_TRUE(decoder.decode(packet, 100.0, out));
  ASSERT_EQ(out.points.size(), 1u);
  const Eigen::Vector3f& p = out.points[0].position;
  const float down = static_cast<float>(std::sin(15.0 * M_PI / 180.0) * 10.0);
  const float across = static_cast<float>(std::cos(15.0 * M_PI / 180.0) * 10.0);
  EXPECT_NEAR(p.x(), 0.0f, 1e-3f);
  EXPECT_NEAR(p.y(), -across, 1e-3f);
  EXPECT_NEAR(p.z(), -down, 1e-3f);
  EXPECT_EQ(out.points[0].ring, 0);  // the lowest beam
  EXPECT_FLOAT_EQ(out.points[0].intensity, 99.0f);
  EXPECT_LT(out.points[0].time, 100.0);  // fired before the packet arrived
  EXPECT_EQ(out.columns.size(), 24u);    // two firing sequences per block
  // The second sequence fires 55.296 us later, halfway to the next block's azimuth (0.4 deg on).
  EXPECT_NEAR(out.columns[1].time - out.columns[0].time, 55.296e-6, 1e-9);
  EXPECT_NEAR(static_cast<double>(out.columns[1].phase) * 36000.0, 9020.0, 0.5);
  EXPECT_NEAR(static_cast<double>(out.columns[2].phase) * 36000.0, 9040.0, 0.5);
  EXPECT_EQ(decoder.stats().rays, 12u * 32u);
  EXPECT_EQ(decoder.stats().model_mismatch, 0u);
}

TEST(VelodyneDecoder, RejectsACalibrationThatDoesNotFitTheModel) {
  EXPECT_THROW(VelodyneDecoder(LidarModel::kHdl32e, nominal_vlp16_calibration()), LidarConfigError);
  EXPECT_THROW(VelodyneDecoder(LidarModel::kOs1, nominal_vlp16_calibration()), LidarConfigError);
}

TEST(VelodyneDecoder, TruncatedForeignAndGarbagePacketsAreSkippedAndCounted) {
  VelodyneDecoder decoder(LidarModel::kHdl32e, nominal_hdl32e_calibration());
  std::vector<std::uint8_t> packet = empty_packet(0, 0x21);
  for (std::size_t b = 0; b < 12; ++b)
    for (std::size_t c = 0; c < 32; ++c)
      set_return(packet, b, c, 5.0);
  DecodedPacket out;
  for (std::size_t length = 0; length < packet.size(); ++length)
    EXPECT_FALSE(decoder.decode(std::span(packet.data(), length), 1.0, out));
  std::vector<std::uint8_t> longer = packet;
  longer.push_back(0);
  EXPECT_FALSE(decoder.decode(longer, 1.0, out));
  EXPECT_EQ(decoder.stats().wrong_size, packet.size() + 1);

  std::vector<std::uint8_t> dual = packet;
  dual[1204] = 0x39;
  EXPECT_FALSE(decoder.decode(dual, 1.0, out));
  EXPECT_EQ(decoder.stats().unsupported_mode, 1u);

  std::mt19937 random(3);
  std::size_t decoded_random = 0;
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<std::uint8_t> garbage(VelodyneDecoder::kPacketSize);
    for (std::uint8_t& byte : garbage)
      byte = static_cast<std::uint8_t>(random());
    garbage[1204] = 0x37;
    decoded_random += decoder.decode(garbage, 1.0, out) ? 1 : 0;
  }
  EXPECT_EQ(decoded_random, 0u);  // random bytes almost never carry a 0xEEFF flag
  EXPECT_EQ(decoder.stats().no_valid_block, 500u);

  // Half the blocks with a foreign flag (HDL-64 lower block) or an impossible azimuth: the rest decodes.
  std::vector<std::uint8_t> mixed = packet;
  for (std::size_t b = 0; b < 12; b += 2)
    mixed[b * 100 + 1] = 0xdd;
  mixed[1 * 100 + 3] = 0xff;  // azimuth >= 36000
  EXPECT_TRUE(decoder.decode(mixed, 1.0, out));
  EXPECT_EQ(decoder.stats().invalid_blocks, 7u);
  EXPECT_EQ(out.points.size(), 5u * 32u);
  EXPECT_EQ(decoder.stats().packets, 1u);
  EXPECT_TRUE(out.points.size() > 0 && out.points.front().position.norm() < 5.1f);
}

TEST(VelodyneDecoder, Hdl32eCaptureGivesItsCompleteRevolutionsOfAbout44kReturns) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "hdl32_example.pcap");
  PcapScanSource source(dir / "hdl32_example.pcap", LidarSetup{LidarModel::kHdl32e, dir / "32db.yaml"});
  std::vector<ScanEvent> scans;
  while (std::optional<ScanEvent> scan = source.next())
    scans.push_back(std::move(*scan));
  // 6 azimuth wraps: 5 complete revolutions, the partial ones at both ends dropped and counted.
  ASSERT_EQ(scans.size(), 5u);
  EXPECT_EQ(source.builder().stats().complete_revolutions, 5u);
  EXPECT_EQ(source.builder().stats().partial_revolutions, 2u);
  EXPECT_EQ(source.builder().stats().wrong_port, 100u);  // the GPS position packets
  EXPECT_EQ(source.builder().decode_stats().packets, 876u);
  EXPECT_EQ(source.builder().decode_stats().skipped(), 0u);
  EXPECT_EQ(source.builder().decode_stats().model_mismatch, 0u);
  std::vector<Eigen::Vector3f> all;
  for (const ScanEvent& scan : scans) {
    std::printf("hdl32e revolution: %zu returns, %zu rays, %.4f s\n", scan.points.size(), scan.rays,
                scan.duration);
    EXPECT_EQ(scan.sensor, "hdl32e");
    EXPECT_GT(scan.points.size(), 42000u);
    EXPECT_LT(scan.points.size(), 46000u);
    EXPECT_NEAR(static_cast<double>(scan.rays), 59230.0, 600.0);  // 32 lasers x ~1851 firings
    EXPECT_NEAR(scan.duration, 0.0852, 0.003);                    // ~11.7 Hz
    all.insert(all.end(), scan.points.begin(), scan.points.end());
  }
  for (std::size_t i = 1; i < scans.size(); ++i)
    EXPECT_NEAR(scans[i].stamp - scans[i - 1].stamp, 0.0852, 0.003);
  test::expect_plausible_geometry(all, "hdl32_example.pcap", 100.0, 4.0, 10.0);  // HDL-32E: 80-100 m
}

/// A VLP-16 capture decoded whole (partial revolutions kept): about one turn of returns.
void expect_plausible_vlp16(const std::filesystem::path& file, std::size_t expected_mismatches) {
  const std::filesystem::path calibration = test::lidar_data_dir() / "VLP16db.yaml";
  PcapScanSource source(file, LidarSetup{LidarModel::kVlp16, calibration, 0, /*keep_partial=*/true});
  std::vector<Eigen::Vector3f> all;
  while (std::optional<ScanEvent> scan = source.next())
    all.insert(all.end(), scan->points.begin(), scan->points.end());
  const DecodeStats& stats = source.builder().decode_stats();
  EXPECT_EQ(stats.packets, 84u);
  EXPECT_EQ(stats.skipped(), 0u);
  EXPECT_EQ(stats.model_mismatch, expected_mismatches);  // counted, not trusted
  EXPECT_EQ(stats.rays, 84u * 12u * 32u);
  test::expect_plausible_geometry(all, file.filename().string(), 100.0, 1.0, 20.0);  // VLP-16: 100 m
}

TEST(VelodyneDecoder, Vlp16CapturesDecodeWithPlausibleGeometry) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "velodyne_example.pcap");
  expect_plausible_vlp16(dir / "velodyne_example.pcap", 0);
  // Early firmware: the product byte says HDL-32E. Decoded as the VLP-16 it is, every packet counted.
  expect_plausible_vlp16(dir / "velodyne_vlp16.pcap", 84);
}

}  // namespace
}  // namespace strata::lidar

namespace strata::lidar {
namespace {

TEST(LidarScanBuilder, CompensatesMotionWhenOdometryCoversTheRevolution) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "hdl32_example.pcap");
  const LidarSetup setup{LidarModel::kHdl32e, dir / "32db.yaml"};
  const std::vector<ScanEvent> measured = read_pcap_scans(dir / "hdl32_example.pcap", setup);
  ASSERT_EQ(measured.size(), 5u);

  // Driving forward at 12.8 m/s (the capture's GPS speed): a point fired at time t, seen again from the
  // end-of-revolution pose, is 12.8 m/s * (end - t) further back along x.
  const auto driving = [](double time) -> std::optional<Eigen::Isometry3d> {
    return Eigen::Isometry3d(Eigen::Translation3d(12.8 * time, 0.0, 0.0));
  };
  PcapScanSource moving(dir / "hdl32_example.pcap", setup);
  moving.builder().set_motion_compensation(driving);
  std::vector<ScanEvent> compensated;
  while (std::optional<ScanEvent> scan = moving.next())
    compensated.push_back(std::move(*scan));
  ASSERT_EQ(compensated.size(), 5u);
  EXPECT_EQ(moving.builder().stats().uncompensated_revolutions, 0u);
  const ScanEvent& before = measured[2];
  const ScanEvent& after = compensated[2];
  ASSERT_EQ(before.points.size(), after.points.size());
  // The first return of the turn moved back by a whole revolution's travel, the last hardly at all.
  EXPECT_NEAR(static_cast<double>(after.points.front().x() - before.points.front().x()),
              -12.8 * before.duration, 0.02);
  EXPECT_NEAR(static_cast<double>(after.points.back().x() - before.points.back().x()), 0.0, 0.01);
  EXPECT_NEAR(static_cast<double>(after.points.front().y() - before.points.front().y()), 0.0, 1e-3);

  // Without odometry for the revolution's times, scans are handed on as measured and counted.
  PcapScanSource blind(dir / "hdl32_example.pcap", setup);
  blind.builder().set_motion_compensation(
      [](double) -> std::optional<Eigen::Isometry3d> { return std::nullopt; });
  std::size_t scans = 0;
  while (std::optional<ScanEvent> scan = blind.next()) {
    EXPECT_EQ(scan->points, measured[scans].points);
    ++scans;
  }
  EXPECT_EQ(scans, 5u);
  EXPECT_EQ(blind.builder().stats().uncompensated_revolutions, 5u);
}

}  // namespace
}  // namespace strata::lidar

namespace strata::lidar {
namespace {

TEST(PcapScanSource, CutCapturesDecodeWhatTheyHoldAndSayTheyWereCut) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "hdl32_example.pcap");
  const std::vector<std::uint8_t> bytes = read_file_bytes(dir / "hdl32_example.pcap");
  const std::filesystem::path cut_file =
      std::filesystem::temp_directory_path() / ("strata_lidar_cut_" + std::to_string(::getpid()) + ".pcap");
  std::size_t previous_complete = 0;
  for (const double fraction : {0.001, 0.2, 0.4, 0.6, 0.8, 0.9999}) {
    const auto size = static_cast<std::size_t>(fraction * static_cast<double>(bytes.size()));
    {
      std::ofstream out(cut_file, std::ios::binary);
      out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(size));
    }
    PcapScanSource source(cut_file, LidarSetup{LidarModel::kHdl32e, dir / "32db.yaml"});
    std::size_t scans = 0;
    while (source.next())
      ++scans;
    EXPECT_TRUE(source.pcap_stats().truncated_file) << fraction;
    EXPECT_LE(scans, 5u);
    EXPECT_GE(scans, previous_complete) << fraction;  // more of the capture, at least as many turns
    previous_complete = scans;
  }
  EXPECT_GE(previous_complete, 4u);
  std::filesystem::remove(cut_file);
}

}  // namespace
}  // namespace strata::lidar

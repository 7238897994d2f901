#include "drivers/lidar/ouster_decoder.hpp"

#include <gtest/gtest.h>

#include <random>

#include "drivers/lidar/lidar_config_error.hpp"
#include "drivers/lidar/pcap_scan_source.hpp"
#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata::lidar {
namespace {

std::string metadata_json(std::size_t beams, const std::string& mode) {
  std::string altitudes;
  std::string azimuths;
  for (std::size_t i = 0; i < beams; ++i) {
    altitudes += (i ? "," : "") + std::to_string(16.0 - 0.5 * static_cast<double>(i));
    azimuths += (i ? "," : "") + std::string("0");
  }
  return R"({"beam_altitude_angles": [)" + altitudes + R"(], "beam_azimuth_angles": [)" + azimuths +
         R"(], "lidar_mode": ")" + mode + R"("})";
}

std::string metadata_error_of(const std::string& json) {
  try {
    (void)parse_ouster_metadata(json, "meta.json");
  } catch (const LidarConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(OusterMetadata, ReadsTheLegacyFileWithOs1Defaults) {
  const std::filesystem::path file = test::lidar_data_dir() / "ouster_example.json";
  STRATA_SKIP_WITHOUT(file);
  const OusterMetadata metadata = read_ouster_metadata(file);
  ASSERT_EQ(metadata.beam_altitude_angles.size(), 64u);
  EXPECT_NEAR(metadata.beam_altitude_angles.front(), 16.856, 1e-9);
  EXPECT_NEAR(metadata.beam_altitude_angles.back(), -16.612, 1e-9);
  EXPECT_EQ(metadata.columns_per_frame, 1024);
  EXPECT_EQ(metadata.frequency, 10);
  EXPECT_EQ(metadata.lidar_origin_to_beam_origin_mm, 0.0);
  EXPECT_EQ(metadata.lidar_to_sensor_transform(0, 0), -1.0);
  EXPECT_EQ(metadata.lidar_to_sensor_transform(2, 3), 36.18);
}

TEST(OusterMetadata, ReadsNewerFieldsAndRejectsBadFilesClearly) {
  std::string json = metadata_json(64, "2048x10");
  json.pop_back();
  json += R"(, "lidar_origin_to_beam_origin_mm": 12.163,
             "lidar_to_sensor_transform": [1,0,0,0, 0,1,0,0, 0,0,1,36.18, 0,0,0,1]})";
  const OusterMetadata metadata = parse_ouster_metadata(json, "inline");
  EXPECT_EQ(metadata.columns_per_frame, 2048);
  EXPECT_DOUBLE_EQ(metadata.lidar_origin_to_beam_origin_mm, 12.163);
  EXPECT_EQ(metadata.lidar_to_sensor_transform(0, 0), 1.0);

  EXPECT_NE(metadata_error_of("{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(metadata_error_of("[1]").find("not a JSON object"), std::string::npos);
  EXPECT_NE(metadata_error_of(R"({"beam_altitude_angles":)" + std::string(100000, '[') +
                              std::string(100000, ']') + "}")
                .find("nested deeper than 64 levels"),
            std::string::npos);
  EXPECT_NE(metadata_error_of("{}").find("beam_altitude_angles"), std::string::npos);
  EXPECT_NE(metadata_error_of(metadata_json(16, "1024x10")).find("has 16 values"), std::string::npos);
  EXPECT_NE(metadata_error_of(metadata_json(64, "1024x15")).find("unknown lidar_mode '1024x15'"),
            std::string::npos);
  EXPECT_NE(metadata_error_of(metadata_json(64, "2048x20")).find("unknown lidar_mode"), std::string::npos);
  EXPECT_THROW((void)read_ouster_metadata("/nonexistent/os1.json"), LidarConfigError);
}

TEST(OusterMetadata, RefusesGeometryThatWouldMakeInfinitePoints) {
  // Finite but absurd values made the decoder's points infinite (the fuzz target's finite-points check).
  const auto with = [](const std::string& field) {
    std::string json = metadata_json(64, "1024x10");
    json.pop_back();
    return json + ", " + field + "}";
  };
  EXPECT_NE(metadata_error_of(with(R"("lidar_origin_to_beam_origin_mm": 1e300)")).find("beyond +-1000 mm"),
            std::string::npos);
  const std::string not_rigid = "is not a rotation and a translation";
  EXPECT_NE(
      metadata_error_of(with(R"("lidar_to_sensor_transform": [1e300,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1])"))
          .find(not_rigid),
      std::string::npos);
  EXPECT_NE(
      metadata_error_of(with(R"("lidar_to_sensor_transform": [1,0,0,0, 0,1,0,0, 0,0,1,1e300, 0,0,0,1])"))
          .find(not_rigid),
      std::string::npos);
  EXPECT_NE(metadata_error_of(with(R"("lidar_to_sensor_transform": [1,0,0,0, 0,1,0,0, 0,0,-1,0, 0,0,0,1])"))
                .find(not_rigid),
            std::string::npos);  // a mirror
  EXPECT_NE(metadata_error_of(with(R"("lidar_to_sensor_transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1])"))
                .find(not_rigid),
            std::string::npos);
  EXPECT_EQ(
      metadata_error_of(with(R"("lidar_to_sensor_transform": [0,-1,0,5, 1,0,0,-5, 0,0,1,38.2, 0,0,0,1])")),
      "");
}

TEST(OusterDecoder, TheCapturedFrameDecodesWithPlausibleGeometry) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "ouster_example.pcap");
  PcapScanSource source(dir / "ouster_example.pcap",
                        LidarSetup{LidarModel::kOs1, dir / "ouster_example.json"});
  std::vector<ScanEvent> scans;
  while (std::optional<ScanEvent> scan = source.next())
    scans.push_back(std::move(*scan));
  // Frames 12072 (columns 800-1023), 12073 (all 1024), 12074 (0-351): one complete revolution.
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(source.builder().stats().partial_revolutions, 2u);
  EXPECT_EQ(source.builder().decode_stats().packets, 100u);
  EXPECT_EQ(source.builder().decode_stats().invalid_blocks, 0u);
  const ScanEvent& scan = scans.front();
  EXPECT_EQ(scan.sensor, "os1-64");
  EXPECT_EQ(scan.rays, 1024u * 64u);
  EXPECT_NEAR(scan.duration, 0.1, 0.002);  // 10 Hz, from the sensor's own column stamps
  test::expect_plausible_geometry(scan.points, "ouster_example.pcap frame", 120.0, 6.0, 16.0);  // OS-1: 120 m
}

TEST(OusterDecoder, TruncatedInvalidAndGarbagePacketsAreSkippedAndCounted) {
  OusterDecoder decoder(parse_ouster_metadata(metadata_json(64, "1024x10"), "inline"));
  std::vector<std::uint8_t> packet(OusterDecoder::kPacketSize, 0);
  for (std::size_t b = 0; b < 16; ++b) {
    std::uint8_t* block = packet.data() + b * 788;
    block[8] = static_cast<std::uint8_t>(b);  // measurement id
    for (std::size_t c = 0; c < 64; ++c)
      block[16 + 12 * c + 1] = 0x10;  // 4096 mm
    std::fill(block + 784, block + 788, 0xff);
  }
  DecodedPacket out;
  ASSERT_TRUE(decoder.decode(packet, 5.0, out));
  EXPECT_EQ(out.points.size(), 16u * 64u);
  EXPECT_NEAR(out.points[0].position.norm(), 4.096, 0.05);  // 36 mm origin offset along z
  for (std::size_t length = 0; length < packet.size(); length += 97)
    EXPECT_FALSE(decoder.decode(std::span(packet.data(), length), 5.0, out));
  std::vector<std::uint8_t> invalid = packet;
  for (std::size_t b = 0; b < 16; ++b)
    invalid[b * 788 + 784] = 0;  // status: not valid
  EXPECT_FALSE(decoder.decode(invalid, 5.0, out));
  std::vector<std::uint8_t> half = packet;
  for (std::size_t b = 0; b < 16; b += 2)
    half[b * 788 + 784] = 0;
  half[1 * 788 + 9] = 0x40;  // measurement id 16385: beyond the frame
  out.clear();
  EXPECT_TRUE(decoder.decode(half, 5.0, out));
  EXPECT_EQ(out.columns.size(), 7u);
  std::mt19937 random(11);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<std::uint8_t> garbage(OusterDecoder::kPacketSize);
    for (std::uint8_t& byte : garbage)
      byte = static_cast<std::uint8_t>(random());
    EXPECT_FALSE(decoder.decode(garbage, 5.0, out));
  }
  EXPECT_EQ(decoder.stats().packets, 2u);
  EXPECT_EQ(decoder.stats().invalid_blocks, 9u);
  EXPECT_EQ(decoder.stats().no_valid_block, 51u);
  EXPECT_EQ(decoder.stats().wrong_size, (packet.size() + 96) / 97);
}

}  // namespace
}  // namespace strata::lidar

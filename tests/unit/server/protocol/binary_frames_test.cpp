#include "server/protocol/binary_frames.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace strata::protocol {
namespace {

std::span<const std::uint8_t> bytes(const std::string& frame) {
  return {reinterpret_cast<const std::uint8_t*>(frame.data()), frame.size()};
}

template <typename T>
T at(const std::string& frame, std::size_t offset) {
  T value;
  std::memcpy(&value, frame.data() + offset, sizeof(T));
  return value;
}

TEST(BinaryFrames, TileLayoutMatchesTheSpec) {
  const EncodedTile tile{-4, 17, 0x0102030405060708ULL, 42, {9, 8, 7}, 1.8e9};
  const std::string frame = encode_tile_frame(tile);
  ASSERT_EQ(frame.size(), kTileHeaderBytes + 3);
  // Byte offsets as proto/PROTOCOL.md lists them.
  EXPECT_EQ(at<std::uint8_t>(frame, 0), 1);
  EXPECT_EQ(at<std::uint8_t>(frame, 1), 1);
  EXPECT_EQ(at<std::uint16_t>(frame, 2), 40);
  EXPECT_EQ(at<std::uint32_t>(frame, 4), 0u);
  EXPECT_EQ(at<std::uint64_t>(frame, 8), 0x0102030405060708ULL);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[8]), 0x08);  // little-endian
  EXPECT_DOUBLE_EQ(at<double>(frame, 16), 1.8e9);
  EXPECT_EQ(at<std::int32_t>(frame, 24), -4);
  EXPECT_EQ(at<std::int32_t>(frame, 28), 17);
  EXPECT_EQ(at<std::uint32_t>(frame, 32), 42u);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[40]), 9);

  const auto decoded = decode_tile_frame(bytes(frame));
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->tile_x, -4);
  EXPECT_EQ(decoded->tile_y, 17);
  EXPECT_EQ(decoded->version, tile.version);
  EXPECT_EQ(decoded->patches, 42u);
  EXPECT_EQ(decoded->draco, tile.draco);
  EXPECT_DOUBLE_EQ(decoded->stamp, tile.stamp);
}

TEST(BinaryFrames, OccupancyRoundTrip) {
  EncodedOccupancy image;
  image.version = 12;
  image.origin_x = -3.25;
  image.origin_y = 8.5;
  image.resolution = 0.1;
  image.level_z = 2.75;
  image.width = 640;
  image.height = 480;
  image.png = {0x89, 'P', 'N', 'G'};
  const std::string frame = encode_occupancy_frame(image);
  EXPECT_EQ(frame.size(), kOccupancyHeaderBytes + 4);
  EXPECT_EQ(at<std::uint8_t>(frame, 0), 2);
  EXPECT_DOUBLE_EQ(at<double>(frame, 24), -3.25);
  EXPECT_DOUBLE_EQ(at<double>(frame, 48), 2.75);
  EXPECT_EQ(at<std::uint32_t>(frame, 56), 640u);
  const auto decoded = decode_occupancy_frame(bytes(frame));
  ASSERT_TRUE(decoded);
  EXPECT_DOUBLE_EQ(decoded->origin_y, 8.5);
  EXPECT_DOUBLE_EQ(decoded->resolution, 0.1);
  EXPECT_EQ(decoded->height, 480);
  EXPECT_EQ(decoded->png, image.png);
}

TEST(BinaryFrames, MalformedFramesAreRefused) {
  const std::string tile = encode_tile_frame(EncodedTile{1, 2, 3, 4, {5}});
  EXPECT_FALSE(decode_tile_frame(bytes(tile.substr(0, 10))));  // shorter than the common header
  EXPECT_FALSE(decode_tile_frame(bytes(tile.substr(0, 20))));  // header says 32 bytes
  EXPECT_FALSE(decode_occupancy_frame(bytes(tile)));           // another kind
  std::string future = tile;
  future[1] = 2;  // a layout this client does not know
  EXPECT_FALSE(decode_tile_frame(bytes(future)));
  std::string longer = tile;
  longer[2] = 48;  // a longer header (newer fields) is skipped by header_bytes
  ASSERT_TRUE(decode_tile_frame(bytes(longer + std::string(8, 'x'))));
}

}  // namespace
}  // namespace strata::protocol

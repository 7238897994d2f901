// The CDR layout ROS 2 puts on the wire and in bags, byte for byte: the encapsulation header, alignment
// counted after it, strings with their NUL and length, sequences with their count, fixed arrays without.
#include "drivers/ros2/cdr_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "drivers/ros2/message_encoding.hpp"

namespace strata::ros2 {
namespace {

using Bytes = std::vector<std::uint8_t>;

/// The value at `offset` after the encapsulation header (copied: CDR aligns to the header's end, not to
/// the buffer's start).
template <typename T>
T at(const Bytes& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + 4 + offset, sizeof(T));
  return value;
}

TEST(CdrWriter, StartsWithTheLittleEndianEncapsulationHeader) {
  EXPECT_EQ(CdrWriter().bytes(), (Bytes{0x00, 0x01, 0x00, 0x00}));
}

TEST(CdrWriter, AlignsEachPrimitiveToItsSizeCountedAfterTheHeader) {
  CdrWriter out;
  out.write(std::uint8_t{0xAB});
  out.write(std::uint16_t{0x0102});  // 1 byte of padding
  out.write(std::uint32_t{0x03040506});
  out.write(double{1.0});  // at 8 after the header: no padding
  out.write(std::uint8_t{0xCD});
  out.write(std::int64_t{-2});                                                      // 7 bytes of padding
  EXPECT_EQ(out.bytes(), (Bytes{0,    1,    0,    0,                                // header
                                0xAB, 0,    0x02, 0x01, 0x06, 0x05, 0x04, 0x03,     // u8, pad, u16, u32
                                0,    0,    0,    0,    0,    0,    0xF0, 0x3F,     // 1.0
                                0xCD, 0,    0,    0,    0,    0,    0,    0,        // u8, 7 pad
                                0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}));  // -2
}

TEST(CdrWriter, WritesAStringAsItsLengthWithTheNulTheBytesAndTheNul) {
  CdrWriter out;
  out.write(std::uint8_t{7});
  out.write_string("map");
  out.write_string("");
  EXPECT_EQ(out.bytes(), (Bytes{0, 1, 0, 0, 7,   0,   0,   0,  // the length is aligned to 4
                                4, 0, 0, 0, 'm', 'a', 'p', 0, 1, 0, 0, 0, 0}));
}

TEST(CdrWriter, WritesSequencesWithTheirCountAndFixedArraysWithout) {
  CdrWriter out;
  out.write_byte_sequence(Bytes{9, 8, 7});
  const double covariance[2] = {0.5, 2.0};
  out.write_doubles(covariance);  // at 8 after the header: 1 byte of padding after the 7
  EXPECT_EQ(out.bytes(), (Bytes{0, 1, 0, 0, 3, 0, 0,    0,    9, 8, 7, 0,  // count, bytes, padding
                                0, 0, 0, 0, 0, 0, 0xE0, 0x3F, 0, 0, 0, 0, 0, 0, 0, 0x40}));
}

TEST(MessageEncoding, OccupancyGridHasTheHeaderMetaDataAndCellsAtTheirOffsets) {
  OccupancyGrid grid;
  grid.header = {{12, 34}, "map"};
  grid.map_load_time = grid.header.stamp;
  grid.resolution = 0.1F;
  grid.width = 2;
  grid.height = 1;
  grid.origin.translation() = Eigen::Vector3d(-1.5, 2.0, 0.0);
  grid.data = {0, -1};
  const Bytes bytes = encode(grid);
  // header: stamp (8) + "map" (4 + 4) = 16; map_load_time 8 -> 24; resolution, width, height -> 36;
  // the pose's 7 doubles from 40 (4 bytes of padding) -> 96; then the cells' count and the cells.
  ASSERT_EQ(bytes.size(), 4U + 96U + 4U + 2U);
  EXPECT_EQ(at<std::int32_t>(bytes, 0), 12);
  EXPECT_EQ(at<std::uint32_t>(bytes, 8), 4U);
  EXPECT_EQ(at<float>(bytes, 24), 0.1F);
  EXPECT_EQ(at<std::uint32_t>(bytes, 28), 2U);
  EXPECT_EQ(at<double>(bytes, 40), -1.5);
  EXPECT_EQ(at<double>(bytes, 88), 1.0);  // orientation.w
  EXPECT_EQ(at<std::uint32_t>(bytes, 96), 2U);
  EXPECT_EQ(bytes[4 + 100], 0);
  EXPECT_EQ(bytes[4 + 101], 0xFF);  // -1: unknown
}

TEST(MessageEncoding, PoseStampedWritesTheRotationAsAUnitQuaternion) {
  PoseStamped pose;
  pose.header.frame_id = "map";
  pose.pose =
      Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ());
  const Bytes bytes = encode(pose);
  ASSERT_EQ(bytes.size(), 4U + 16U + 7U * 8U);
  EXPECT_EQ(at<double>(bytes, 16), 1.0);
  EXPECT_EQ(at<double>(bytes, 32), 3.0);
  EXPECT_NEAR(at<double>(bytes, 56), std::sqrt(0.5), 1e-12);  // z
  EXPECT_NEAR(at<double>(bytes, 64), std::sqrt(0.5), 1e-12);  // w
}

TEST(MessageEncoding, OdometryAlignsEachPartAfterTheStrings) {
  Odometry odometry;
  odometry.header.frame_id = "odom";                            // 8 + 4 + 5 = 17 bytes
  odometry.child_frame_id = "base_link";                        // from 20: 4 + 10 -> 34
  odometry.pose.pose.translation() = Eigen::Vector3d(1, 2, 3);  // from 40: 7 doubles -> 96
  odometry.pose.covariance[35] = 0.25;                          // 36 doubles -> 384
  odometry.twist.twist.linear.x() = 0.5;                        // 6 doubles -> 432, then 36 -> 720
  odometry.twist.covariance[0] = 4.0;
  const Bytes bytes = encode(odometry);
  ASSERT_EQ(bytes.size(), 4U + 720U);
  EXPECT_EQ(at<std::uint32_t>(bytes, 20), 10U);
  EXPECT_EQ(at<double>(bytes, 40), 1.0);
  EXPECT_EQ(at<double>(bytes, 88), 1.0);  // orientation.w
  EXPECT_EQ(at<double>(bytes, 96 + 35 * 8), 0.25);
  EXPECT_EQ(at<double>(bytes, 384), 0.5);
  EXPECT_EQ(at<double>(bytes, 432), 4.0);
}

TEST(MessageEncoding, TfAndPoseWithCovarianceHaveTheirSequenceAndArrayLayouts) {
  TFMessage tf;
  tf.transforms.push_back({{{1, 2}, "map"}, "base_link", Eigen::Isometry3d(Eigen::Translation3d(7, 8, 9))});
  const Bytes tf_bytes = encode(tf);
  // count 4; stamp 8 -> 12; "map" 8 -> 20; "base_link" 14 -> 34; the transform from 40, 7 doubles.
  ASSERT_EQ(tf_bytes.size(), 4U + 96U);
  EXPECT_EQ(at<std::uint32_t>(tf_bytes, 0), 1U);
  EXPECT_EQ(at<double>(tf_bytes, 40), 7.0);

  PoseWithCovarianceStamped pose;
  pose.header.frame_id = "map";
  pose.pose.covariance[0] = 0.01;
  const Bytes pose_bytes = encode(pose);
  ASSERT_EQ(pose_bytes.size(), 4U + 16U + 56U + 288U);
  EXPECT_EQ(at<double>(pose_bytes, 72), 0.01);
}

}  // namespace
}  // namespace strata::ros2

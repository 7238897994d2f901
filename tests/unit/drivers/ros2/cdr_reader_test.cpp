// The CDR reader and the decoders a replay uses read back what the encoder wrote, and refuse a message cut
// short.
#include "drivers/ros2/cdr_reader.hpp"

#include <gtest/gtest.h>

#include "drivers/ros2/message_decoding.hpp"
#include "drivers/ros2/message_encoding.hpp"

namespace strata::ros2 {
namespace {

PointCloud2 sample_cloud() {
  PointCloud2 cloud;
  cloud.header = {Time{12, 345}, "sensor"};
  cloud.fields = {{"x", 0}, {"y", 4}, {"z", 8}, {"time", 12}};
  cloud.width = 3;
  cloud.point_step = 16;
  cloud.row_step = 48;
  for (int i = 0; i < 48; ++i)
    cloud.data.push_back(static_cast<std::uint8_t>(i * 5));
  return cloud;
}

TEST(CdrReader, APointCloudAndAStringReadBackAsWritten) {
  const PointCloud2 cloud = sample_cloud();
  const PointCloud2 back = decode_point_cloud(encode(cloud));
  EXPECT_EQ(back.header.stamp.sec, 12);
  EXPECT_EQ(back.header.stamp.nanosec, 345U);
  EXPECT_EQ(back.header.frame_id, "sensor");
  ASSERT_EQ(back.fields.size(), 4U);
  EXPECT_EQ(back.fields[3].name, "time");
  EXPECT_EQ(back.fields[3].offset, 12U);
  EXPECT_EQ(back.fields[3].datatype, PointField::kFloat32);
  EXPECT_EQ(back.width, 3U);
  EXPECT_EQ(back.point_step, 16U);
  EXPECT_EQ(back.data, cloud.data);
  EXPECT_TRUE(back.is_dense);
  EXPECT_EQ(decode_string(encode(String{"a,b,1.5"})).data, "a,b,1.5");
  EXPECT_EQ(decode_string(encode(String{""})).data, "");
}

TEST(CdrReader, AMessageCutShortOrWithoutTheHeaderIsRefused) {
  const std::vector<std::uint8_t> bytes = encode(sample_cloud());
  for (std::size_t cut = 0; cut + 1 < bytes.size(); ++cut)
    EXPECT_THROW((void)decode_point_cloud(std::span(bytes).first(cut)), CdrError) << cut;
  std::vector<std::uint8_t> big_endian = bytes;
  big_endian[1] = 0x00;  // CDR_BE
  EXPECT_THROW((void)decode_point_cloud(big_endian), CdrError);
}

}  // namespace
}  // namespace strata::ros2

#include "drivers/ros2/message_decoding.hpp"

#include "drivers/ros2/cdr_reader.hpp"

namespace strata::ros2 {

PointCloud2 decode_point_cloud(std::span<const std::uint8_t> bytes) {
  CdrReader in(bytes);
  PointCloud2 cloud;
  cloud.header.stamp.sec = in.read<std::int32_t>();
  cloud.header.stamp.nanosec = in.read<std::uint32_t>();
  cloud.header.frame_id = in.read_string();
  cloud.height = in.read<std::uint32_t>();
  cloud.width = in.read<std::uint32_t>();
  const std::uint32_t fields = in.read_sequence_size();
  for (std::uint32_t i = 0; i < fields; ++i) {
    PointField field;
    field.name = in.read_string();
    field.offset = in.read<std::uint32_t>();
    field.datatype = in.read<std::uint8_t>();
    field.count = in.read<std::uint32_t>();
    cloud.fields.push_back(std::move(field));
  }
  cloud.is_bigendian = in.read<std::uint8_t>() != 0;
  cloud.point_step = in.read<std::uint32_t>();
  cloud.row_step = in.read<std::uint32_t>();
  const auto data = in.read_byte_sequence();
  cloud.data.assign(data.begin(), data.end());
  cloud.is_dense = in.read<std::uint8_t>() != 0;
  return cloud;
}

String decode_string(std::span<const std::uint8_t> bytes) {
  CdrReader in(bytes);
  return String{in.read_string()};
}

}  // namespace strata::ros2

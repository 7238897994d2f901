#include "drivers/io/pcd_writer.hpp"

#include <cstring>

namespace strata::io {

std::string encode_binary_pcd(const std::vector<Eigen::Vector3f>& points) {
  const std::string count = std::to_string(points.size());
  std::string data =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x y z\n"
      "SIZE 4 4 4\n"
      "TYPE F F F\n"
      "COUNT 1 1 1\n"
      "WIDTH " +
      count +
      "\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS " +
      count + "\nDATA binary\n";
  const std::size_t header = data.size();
  data.resize(header + points.size() * 3 * sizeof(float));
  char* out = data.data() + header;
  for (const Eigen::Vector3f& point : points) {
    // PCD binary data is in the machine's byte order, as PCL writes it (little-endian wherever Strata runs).
    std::memcpy(out, point.data(), 3 * sizeof(float));
    out += 3 * sizeof(float);
  }
  return data;
}

}  // namespace strata::io

#include "drivers/io/pcd_writer.hpp"

#include <cstring>

namespace strata::io {

std::string encode_binary_pcd(const std::vector<Eigen::Vector3f>& points, const std::vector<float>& times) {
  const bool timed = !times.empty() && times.size() == points.size();
  const std::string count = std::to_string(points.size());
  std::string data =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n";
  data += timed ? "FIELDS x y z time\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
                : "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  data += "WIDTH " + count +
          "\n"
          "HEIGHT 1\n"
          "VIEWPOINT 0 0 0 1 0 0 0\n"
          "POINTS " +
          count + "\nDATA binary\n";
  const std::size_t header = data.size();
  const std::size_t record = (timed ? 4 : 3) * sizeof(float);
  data.resize(header + points.size() * record);
  char* out = data.data() + header;
  for (std::size_t i = 0; i < points.size(); ++i) {
    // PCD binary data is in the machine's byte order, as PCL writes it (little-endian wherever Strata runs).
    std::memcpy(out, points[i].data(), 3 * sizeof(float));
    if (timed)
      std::memcpy(out + 3 * sizeof(float), &times[i], sizeof(float));
    out += record;
  }
  return data;
}

}  // namespace strata::io

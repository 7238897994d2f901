#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace strata::io {

/// A binary PCD file (v0.7) of x, y, z as float32: what PCL and read_pcd() read. The points go out
/// bit for bit, so a scan written and read back is the same scan.
[[nodiscard]] std::string encode_binary_pcd(const std::vector<Eigen::Vector3f>& points);

}  // namespace strata::io

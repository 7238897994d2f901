#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace strata::io {

/// A binary PCD file (v0.7) of x, y, z as float32: what PCL and read_pcd() read. The points go out
/// bit for bit, so a scan written and read back is the same scan. `times`, one per point: a "time" field
/// too (seconds from the scan's stamp, ScanEvent::point_times), so a replay deskews as the live run did.
[[nodiscard]] std::string encode_binary_pcd(const std::vector<Eigen::Vector3f>& points,
                                            const std::vector<float>& times = {});

}  // namespace strata::io

#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace strata::lidar {

/// The sensors this driver decodes. Always chosen by the user: packets' product bytes are not trusted
/// (a real VLP-16 capture reports the HDL-32E id).
enum class LidarModel { kVlp16, kHdl32e, kOs1 };

/// "vlp16", "hdl32e" (or "hdl32"), "os1" (or "os1-64"); throws LidarConfigError naming the choices.
[[nodiscard]] LidarModel parse_lidar_model(std::string_view name);
/// The sensor name scans carry: "vlp16", "hdl32e", "os1-64".
[[nodiscard]] std::string sensor_name(LidarModel model);
/// The UDP port the sensor sends its point data to by default (Velodyne 2368, Ouster 7502).
[[nodiscard]] std::uint16_t default_data_port(LidarModel model);
/// Data packets per second at the datasheet's default setting (VLP-16 single return 754, HDL-32E 1808,
/// OS-1-64 in 1024x10 640), for real-time ratios.
[[nodiscard]] double nominal_packet_rate(LidarModel model);

/// Ring numbers for beams given their elevations: 0 for the lowest beam, counting up.
[[nodiscard]] std::vector<std::uint16_t> rings_by_elevation(const std::vector<double>& elevations);

}  // namespace strata::lidar

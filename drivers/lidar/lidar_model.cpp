#include "drivers/lidar/lidar_model.hpp"

#include <algorithm>
#include <numeric>

#include "drivers/lidar/lidar_config_error.hpp"

namespace strata::lidar {

LidarModel parse_lidar_model(std::string_view name) {
  if (name == "vlp16")
    return LidarModel::kVlp16;
  if (name == "hdl32e" || name == "hdl32")
    return LidarModel::kHdl32e;
  if (name == "os1" || name == "os1-64")
    return LidarModel::kOs1;
  throw LidarConfigError("unknown lidar model '" + std::string(name) + "' (vlp16, hdl32e or os1)");
}

std::string sensor_name(LidarModel model) {
  switch (model) {
    case LidarModel::kVlp16:
      return "vlp16";
    case LidarModel::kHdl32e:
      return "hdl32e";
    case LidarModel::kOs1:
      return "os1-64";
  }
  return "lidar";
}

std::uint16_t default_data_port(LidarModel model) {
  return model == LidarModel::kOs1 ? 7502 : 2368;
}

double nominal_packet_rate(LidarModel model) {
  switch (model) {
    case LidarModel::kVlp16:
      return 754.0;
    case LidarModel::kHdl32e:
      return 1808.0;
    case LidarModel::kOs1:
      return 640.0;
  }
  return 0.0;
}

std::vector<std::uint16_t> rings_by_elevation(const std::vector<double>& elevations) {
  std::vector<std::size_t> order(elevations.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return elevations[a] < elevations[b]; });
  std::vector<std::uint16_t> rings(elevations.size());
  for (std::size_t rank = 0; rank < order.size(); ++rank)
    rings[order[rank]] = static_cast<std::uint16_t>(rank);
  return rings;
}

}  // namespace strata::lidar

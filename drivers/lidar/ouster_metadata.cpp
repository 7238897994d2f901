#include "drivers/lidar/ouster_metadata.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "drivers/io/json_input.hpp"
#include "drivers/lidar/lidar_config_error.hpp"

namespace strata::lidar {
namespace {

constexpr std::size_t kLegacyChannels = 64;  // the legacy packet always carries 64 channels
// The decoder shifts and turns every return by these in float: finite but absurd values (1e300) made
// infinite points (the fuzz target's finite-points check). Real sensors: a beam origin of 0 to 28 mm, a
// housing of centimetres.
constexpr double kMaxBeamOriginMm = 1000.0;
constexpr double kMaxTranslationMm = 10000.0;

/// A rotation (orthonormal, det +1, to the precision of printed decimals) and a bounded translation, over
/// the bottom row 0 0 0 1.
bool is_rigid(const Eigen::Matrix4d& transform) {
  const Eigen::Matrix3d rotation = transform.topLeftCorner<3, 3>();
  return (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-3 &&
         rotation.determinant() > 0.0 &&
         transform.topRightCorner<3, 1>().cwiseAbs().maxCoeff() <= kMaxTranslationMm &&
         transform.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1));
}

std::vector<double> angles(const nlohmann::json& root, const char* key, std::string_view source) {
  const auto field = root.find(key);
  if (field == root.end() || !field->is_array())
    throw LidarConfigError(std::string(source) + ": no '" + key + "' array (not an Ouster metadata file?)");
  if (field->size() != kLegacyChannels)
    throw LidarConfigError(std::string(source) + ": '" + key + "' has " + std::to_string(field->size()) +
                           " values; the OS-1 1.x packet has " + std::to_string(kLegacyChannels) +
                           " channels");
  std::vector<double> values;
  for (const nlohmann::json& value : *field) {
    if (!value.is_number() || !std::isfinite(value.get<double>()) || std::abs(value.get<double>()) > 90.0)
      throw LidarConfigError(std::string(source) + ": '" + key +
                             "' holds a value that is not an angle in degrees");
    values.push_back(value.get<double>());
  }
  return values;
}

}  // namespace

OusterMetadata parse_ouster_metadata(const std::string& json_text, std::string_view source) {
  const io::JsonInput input = io::parse_json(json_text);
  if (!input.ok())
    throw LidarConfigError(std::string(source) + ": " + input.error);
  const nlohmann::json& root = input.value;
  if (!root.is_object())
    throw LidarConfigError(std::string(source) + ": not a JSON object");
  OusterMetadata metadata;
  metadata.beam_altitude_angles = angles(root, "beam_altitude_angles", source);
  metadata.beam_azimuth_angles = angles(root, "beam_azimuth_angles", source);

  const auto mode = root.find("lidar_mode");
  if (mode == root.end() || !mode->is_string())
    throw LidarConfigError(std::string(source) + ": no 'lidar_mode' string (e.g. \"1024x10\")");
  const std::string text = mode->get<std::string>();
  const std::size_t x = text.find('x');
  const std::string width = x == std::string::npos ? "" : text.substr(0, x);
  const std::string rate = x == std::string::npos ? "" : text.substr(x + 1);
  if (!((width == "512" || width == "1024" || width == "2048") && (rate == "10" || rate == "20")) ||
      (width == "2048" && rate == "20"))
    throw LidarConfigError(std::string(source) + ": unknown lidar_mode '" + text +
                           "' (512x10, 512x20, 1024x10, 1024x20 or 2048x10)");
  metadata.columns_per_frame = std::stoi(width);
  metadata.frequency = std::stoi(rate);

  if (const auto origin = root.find("lidar_origin_to_beam_origin_mm"); origin != root.end()) {
    if (!origin->is_number() || !std::isfinite(origin->get<double>()))
      throw LidarConfigError(std::string(source) + ": lidar_origin_to_beam_origin_mm is not a number");
    metadata.lidar_origin_to_beam_origin_mm = origin->get<double>();
    if (std::abs(metadata.lidar_origin_to_beam_origin_mm) > kMaxBeamOriginMm)
      throw LidarConfigError(std::string(source) + ": lidar_origin_to_beam_origin_mm beyond +-" +
                             std::to_string(static_cast<int>(kMaxBeamOriginMm)) + " mm");
  }
  metadata.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
  if (const auto transform = root.find("lidar_to_sensor_transform"); transform != root.end()) {
    if (!transform->is_array() || transform->size() != 16)
      throw LidarConfigError(std::string(source) +
                             ": lidar_to_sensor_transform is not 16 numbers (row-major 4x4)");
    for (std::size_t i = 0; i < 16; ++i) {
      const nlohmann::json& value = (*transform)[i];
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        throw LidarConfigError(std::string(source) + ": lidar_to_sensor_transform holds a non-number");
      metadata.lidar_to_sensor_transform(static_cast<Eigen::Index>(i / 4), static_cast<Eigen::Index>(i % 4)) =
          value.get<double>();
    }
    if (!is_rigid(metadata.lidar_to_sensor_transform))
      throw LidarConfigError(std::string(source) +
                             ": lidar_to_sensor_transform is not a rotation and a translation within +-" +
                             std::to_string(static_cast<int>(kMaxTranslationMm)) + " mm");
  }
  return metadata;
}

OusterMetadata read_ouster_metadata(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file)
    throw LidarConfigError(path.string() + ": cannot open the Ouster metadata file");
  std::ostringstream text;
  text << file.rdbuf();
  return parse_ouster_metadata(text.str(), path.string());
}

}  // namespace strata::lidar

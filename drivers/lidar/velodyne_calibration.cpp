#include "drivers/lidar/velodyne_calibration.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <utility>

#include "drivers/lidar/lidar_config_error.hpp"

namespace strata::lidar {
namespace {

/// No laser's length correction comes near this; beyond it the file is in millimetres or corrupt.
constexpr double kMaxCorrectionMetres = 10.0;

double number(const YAML::Node& laser, const char* key, std::string_view source, std::size_t index,
              bool required) {
  const YAML::Node value = laser[key];
  if (!value) {
    if (required)
      throw LidarConfigError(std::string(source) + ": laser entry " + std::to_string(index) + " has no " +
                             key);
    return 0.0;
  }
  try {
    const double result = value.as<double>();
    if (!std::isfinite(result))
      throw YAML::Exception(value.Mark(), "not finite");
    return result;
  } catch (const YAML::Exception&) {
    throw LidarConfigError(std::string(source) + ": laser entry " + std::to_string(index) + ": " + key +
                           " is not a number");
  }
}

VelodyneCalibration from_elevations_deg(const std::vector<double>& elevations) {
  VelodyneCalibration calibration;
  for (std::size_t i = 0; i < elevations.size(); ++i) {
    VelodyneLaser laser;
    laser.laser_id = static_cast<int>(i);
    laser.vert_correction = elevations[i] * std::numbers::pi / 180.0;
    calibration.lasers.push_back(laser);
  }
  return calibration;
}

}  // namespace

VelodyneCalibration parse_velodyne_calibration(const std::string& yaml_text, std::string_view source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& error) {
    throw LidarConfigError(std::string(source) + ": not valid YAML: " + error.what());
  }
  if (!root.IsMap() || !root["lasers"] || !root["lasers"].IsSequence() || root["lasers"].size() == 0)
    throw LidarConfigError(std::string(source) + ": no 'lasers' list (not a Velodyne calibration file?)");

  VelodyneCalibration calibration;
  if (const YAML::Node resolution = root["distance_resolution"]) {
    try {
      calibration.distance_resolution = resolution.as<double>();
    } catch (const YAML::Exception&) {
      throw LidarConfigError(std::string(source) + ": distance_resolution is not a number");
    }
    if (!(calibration.distance_resolution > 0.0 && calibration.distance_resolution < 1.0))
      throw LidarConfigError(std::string(source) + ": distance_resolution must be in (0, 1) m");
  }

  const YAML::Node lasers = root["lasers"];
  std::vector<VelodyneLaser> by_id(lasers.size());
  std::vector<bool> seen(lasers.size(), false);
  for (std::size_t i = 0; i < lasers.size(); ++i) {
    const YAML::Node entry = lasers[i];
    if (!entry.IsMap())
      throw LidarConfigError(std::string(source) + ": laser entry " + std::to_string(i) + " is not a map");
    VelodyneLaser laser;
    const double id = number(entry, "laser_id", source, i, true);
    if (id < 0.0 || id >= static_cast<double>(lasers.size()) || id != std::floor(id))
      throw LidarConfigError(std::string(source) + ": laser entry " + std::to_string(i) + ": laser_id " +
                             std::to_string(id) + " is not in 0.." + std::to_string(lasers.size() - 1));
    laser.laser_id = static_cast<int>(id);
    if (seen[static_cast<std::size_t>(laser.laser_id)])
      throw LidarConfigError(std::string(source) + ": laser_id " + std::to_string(laser.laser_id) +
                             " appears twice");
    seen[static_cast<std::size_t>(laser.laser_id)] = true;
    laser.vert_correction = number(entry, "vert_correction", source, i, true);
    laser.rot_correction = number(entry, "rot_correction", source, i, false);
    laser.dist_correction = number(entry, "dist_correction", source, i, false);
    laser.dist_correction_x = number(entry, "dist_correction_x", source, i, false);
    laser.dist_correction_y = number(entry, "dist_correction_y", source, i, false);
    laser.vert_offset_correction = number(entry, "vert_offset_correction", source, i, false);
    laser.horiz_offset_correction = number(entry, "horiz_offset_correction", source, i, false);
    laser.focal_distance = number(entry, "focal_distance", source, i, false);
    laser.focal_slope = number(entry, "focal_slope", source, i, false);
    if (std::abs(laser.vert_correction) > std::numbers::pi / 2)
      throw LidarConfigError(std::string(source) + ": laser_id " + std::to_string(laser.laser_id) +
                             ": vert_correction beyond +-pi/2 (the file's angles must be radians)");
    // The decoder turns every return by these in float: a finite but absurd value (1e300) made infinite
    // points (a fuzzed file found it). Real corrections are a few centimetres to a metre, and milliradians.
    if (std::abs(laser.rot_correction) > 2 * std::numbers::pi)
      throw LidarConfigError(std::string(source) + ": laser_id " + std::to_string(laser.laser_id) +
                             ": rot_correction beyond +-2 pi (the file's angles must be radians)");
    for (const auto& [name, metres] : {std::pair{"dist_correction", laser.dist_correction},
                                       std::pair{"dist_correction_x", laser.dist_correction_x},
                                       std::pair{"dist_correction_y", laser.dist_correction_y},
                                       std::pair{"vert_offset_correction", laser.vert_offset_correction},
                                       std::pair{"horiz_offset_correction", laser.horiz_offset_correction}}) {
      if (std::abs(metres) > kMaxCorrectionMetres)
        throw LidarConfigError(std::string(source) + ": laser_id " + std::to_string(laser.laser_id) + ": " +
                               name + " beyond +-" + std::to_string(static_cast<int>(kMaxCorrectionMetres)) +
                               " m (the file's lengths must be metres)");
    }
    by_id[static_cast<std::size_t>(laser.laser_id)] = laser;
  }
  if (const YAML::Node count = root["num_lasers"]) {
    int declared = -1;
    try {
      declared = count.as<int>();
    } catch (const YAML::Exception&) {
      throw LidarConfigError(std::string(source) + ": num_lasers is not an integer");
    }
    if (declared != static_cast<int>(lasers.size()))
      throw LidarConfigError(std::string(source) + ": num_lasers is " + std::to_string(declared) + " but " +
                             std::to_string(lasers.size()) + " lasers are listed");
  }
  calibration.lasers = std::move(by_id);
  return calibration;
}

VelodyneCalibration read_velodyne_calibration(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file)
    throw LidarConfigError(path.string() + ": cannot open the Velodyne calibration file");
  std::ostringstream text;
  text << file.rdbuf();
  return parse_velodyne_calibration(text.str(), path.string());
}

VelodyneCalibration nominal_vlp16_calibration() {
  // VLP-16 user manual: lasers alternate below and above the horizon, -15..+15 deg in 2 deg steps.
  std::vector<double> elevations;
  for (int i = 0; i < 16; ++i)
    elevations.push_back(i % 2 == 0 ? i - 15.0 : static_cast<double>(i));
  return from_elevations_deg(elevations);
}

VelodyneCalibration nominal_hdl32e_calibration() {
  // HDL-32E manual: 4/3 deg apart from -30.67 to +10.67 deg, interleaved lower/upper half.
  std::vector<double> elevations;
  for (int i = 0; i < 32; ++i)
    elevations.push_back((i % 2 == 0 ? -30.67 : -9.33) + static_cast<double>(i / 2) * (4.0 / 3.0));
  return from_elevations_deg(elevations);
}

}  // namespace strata::lidar

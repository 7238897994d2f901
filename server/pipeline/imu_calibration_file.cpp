#include "server/pipeline/imu_calibration_file.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "drivers/io/json_input.hpp"

namespace strata::pipeline {
namespace {

constexpr const char* kFormat = "strata-imu-calibration";
constexpr int kVersion = 1;
constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;
/// A mounting error beyond this is no calibration to start from, whatever wrote it: the levelling takes
/// out small errors, and 10 degrees is an IMU bolted on askew.
constexpr double kMaxMountingDeg = 10.0;

}  // namespace

ImuCalibration parse_imu_calibration(const std::string& text) {
  const io::JsonInput input = io::parse_json(text);
  if (!input.ok())
    throw std::runtime_error(input.error);
  const nlohmann::json& json = input.value;
  if (!json.is_object())
    throw std::runtime_error("not a JSON object");
  // value("format", "") would throw nlohmann's type_error for a format that is no string: not the
  // runtime_error this promises (a fuzzed file found it).
  const auto format = json.find("format");
  if (format == json.end() || !format->is_string() || format->get<std::string>() != kFormat)
    throw std::runtime_error(std::string("no \"format\": \"") + kFormat + "\"");
  if (!json.contains("version") || !json["version"].is_number_integer() ||
      json["version"].get<int>() != kVersion)
    throw std::runtime_error("version " + json.value("version", nlohmann::json()).dump().substr(0, 40) +
                             ", expected " + std::to_string(kVersion));
  const auto number = [&](const char* key) {
    if (!json.contains(key) || !json[key].is_number() || !std::isfinite(json[key].get<double>()))
      throw std::runtime_error(std::string("\"") + key + "\" is not a finite number");
    return json[key].get<double>();
  };
  const auto count = [&](const char* key) {
    if (!json.contains(key) || !json[key].is_number_unsigned())
      throw std::runtime_error(std::string("\"") + key + "\" is not a count");
    return json[key].get<std::size_t>();
  };
  if (!json.contains("imu") || !json["imu"].is_string() || json["imu"].get<std::string>().empty())
    throw std::runtime_error("\"imu\" does not name the IMU");
  ImuCalibration calibration;
  calibration.imu = json["imu"].get<std::string>();
  const double roll = number("mounting_roll_deg");
  const double pitch = number("mounting_pitch_deg");
  if (std::abs(roll) > kMaxMountingDeg || std::abs(pitch) > kMaxMountingDeg)
    throw std::runtime_error("a mounting error of more than " + std::to_string(kMaxMountingDeg) + " degrees");
  calibration.mounting = Eigen::Vector2d(roll, pitch) / kDegreesPerRadian;
  calibration.loops = count("loops");
  calibration.keyframes = count("keyframes");
  return calibration;
}

std::string format_imu_calibration(const ImuCalibration& calibration) {
  const nlohmann::json json{{"format", kFormat},
                            {"version", kVersion},
                            {"imu", calibration.imu},
                            {"mounting_roll_deg", calibration.mounting.x() * kDegreesPerRadian},
                            {"mounting_pitch_deg", calibration.mounting.y() * kDegreesPerRadian},
                            {"loops", calibration.loops},
                            {"keyframes", calibration.keyframes}};
  return json.dump(2) + "\n";
}

}  // namespace strata::pipeline

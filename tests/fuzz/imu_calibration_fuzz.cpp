// The IMU calibration file (strata serve --imu-calibration FILE: JSON the server wrote at an earlier run's
// loop closure, read at start). The parser either refuses the text (std::runtime_error saying why: not JSON,
// nested too deep, another format or version, a field missing or out of range) or returns a named IMU
// mounted within 10 degrees; what it returns writes back to a file that parses to the same calibration.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>

#include "server/pipeline/imu_calibration_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  strata::pipeline::ImuCalibration calibration;
  try {
    calibration =
        strata::pipeline::parse_imu_calibration(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::runtime_error&) {
    return 0;
  }
  constexpr double kTenDegrees = 10.0 * std::numbers::pi / 180.0;
  if (calibration.imu.empty() || !calibration.mounting.allFinite() ||
      calibration.mounting.cwiseAbs().maxCoeff() > kTenDegrees * (1 + 1e-12))
    __builtin_trap();
  const strata::pipeline::ImuCalibration again =
      strata::pipeline::parse_imu_calibration(strata::pipeline::format_imu_calibration(calibration));
  if (again.imu != calibration.imu || again.loops != calibration.loops ||
      again.keyframes != calibration.keyframes ||
      (again.mounting - calibration.mounting).cwiseAbs().maxCoeff() > 1e-15)
    __builtin_trap();  // the file the server writes reads back as what it kept
  return 0;
}

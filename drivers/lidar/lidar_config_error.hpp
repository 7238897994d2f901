#pragma once

#include <stdexcept>
#include <string>

namespace strata::lidar {

/// A lidar setup that cannot be used: an unreadable or invalid calibration / metadata file, an unknown
/// model name, a calibration that does not fit the model. The message names the file and the problem.
class LidarConfigError : public std::runtime_error {
 public:
  explicit LidarConfigError(const std::string& problem) : std::runtime_error(problem) {}
};

}  // namespace strata::lidar

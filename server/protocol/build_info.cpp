#include "server/protocol/build_info.hpp"

#include <draco/core/draco_version.h>
#include <spdlog/version.h>

#include <Eigen/Core>
#include <boost/beast/version.hpp>
#include <boost/version.hpp>
#include <opencv2/core/version.hpp>

#ifndef STRATA_VERSION
#error "STRATA_VERSION must be defined by the build"
#endif

namespace strata::build_info {

std::string version() {
  return STRATA_VERSION;
}

nlohmann::json libraries() {
  auto dotted = [](int major, int minor, int patch) {
    return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
  };
  return {{"boost", dotted(BOOST_VERSION / 100000, BOOST_VERSION / 100 % 1000, BOOST_VERSION % 100)},
          {"eigen", dotted(EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)},
          {"draco", draco::kDracoVersion},
          {"opencv", CV_VERSION},
          {"nlohmann_json",
           dotted(NLOHMANN_JSON_VERSION_MAJOR, NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH)},
          {"spdlog", dotted(SPDLOG_VER_MAJOR, SPDLOG_VER_MINOR, SPDLOG_VER_PATCH)}};
}

}  // namespace strata::build_info

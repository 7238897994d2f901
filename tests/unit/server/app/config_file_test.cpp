#include "server/app/config_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "server/app/serve_command.hpp"

namespace strata::app {
namespace {

/// Parses `strata serve --config FILE` with FILE holding `contents`, as main() does.
void parse_config(const std::string& contents, ServeOptions& options) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("strata-config-file-test-" + std::to_string(::getpid()) + ".ini");
  std::ofstream(file) << contents;
  CLI::App app{"Strata", "strata"};
  static_cast<void>(add_serve_command(app, options));
  allow_config_file(app);
  try {
    parse_options([&] { app.parse("serve --config " + file.string(), false); });
  } catch (...) {
    std::filesystem::remove(file);
    throw;
  }
  std::filesystem::remove(file);
}

TEST(ConfigFile, SetsTheServeOptions) {
  ServeOptions options;
  parse_config("[serve]\nport = 9000\nno-imu-calibration = true\n", options);
  EXPECT_EQ(options.network.port, 9000);
  EXPECT_FALSE(options.keep_imu_calibration);
}

TEST(ConfigFile, AFlagsNumberBeyond64BitsIsAParseErrorNotACrash) {
  // std::stoll's std::out_of_range escaped CLI11 2.1 and ended the process (found by the fuzz target).
  ServeOptions options;
  EXPECT_THROW(parse_config("[serve]\nno-imu-calibration = 2222222222222222222222\n", options),
               CLI::ParseError);
  EXPECT_THROW(parse_config("[serve]\nkeep-going = 1\n", options), CLI::ParseError);  // no such option
}

}  // namespace
}  // namespace strata::app

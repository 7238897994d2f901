// The config file (strata serve --config FILE, deploy/strata.ini: INI or TOML, the long options of `strata
// serve` under [serve]), parsed by the same command-line application main() builds: CLI11's config reader,
// then every option's conversion and check, through parse_options as main() parses. A file is either refused
// with a CLI::ParseError (what main() catches and explains) or gives options within the ranges the options
// declare.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "server/app/config_file.hpp"
#include "server/app/serve_command.hpp"
#include "server/auth/host_policy.hpp"
#include "server/auth/request_auth.hpp"

namespace {

bool within(double value, double low, double high) {
  return value >= low && value <= high;
}

/// Traps unless every checked option is in the range its declaration allows.
void check(const strata::app::ServeOptions& options) {
  const auto& network = options.network;
  const auto& robot = options.robot;
  if (!within(network.pose_rate, 1.0, 1000.0) || !within(options.time_scale, 0.01, 100.0) ||
      !within(static_cast<double>(network.io_threads), 1, 64) || !within(robot.radius, 0.05, 5.0) ||
      !within(robot.height, 0.1, 5.0) || !within(robot.max_step, 0.0, 1.0) ||
      !within(robot.max_slope_deg, 0.0, 60.0) || !within(options.replay.noise_translation, 0.0, 1.0) ||
      !within(options.replay.noise_rotation_deg, 0.0, 90.0) || !within(options.sensor_timeout, 0.0, 3600.0) ||
      !within(network.client_timeout_s, 2.0, 3600.0) ||
      !within(static_cast<double>(network.max_clients), 1, 100000) ||
      !within(static_cast<double>(network.max_http_connections), 1, 100000) ||
      !within(static_cast<double>(network.max_connections_per_address), 1, 100000))
    __builtin_trap();
  for (const std::string& origin : network.allowed_origins) {
    if (!strata::auth::is_valid_origin_pattern(origin))
      __builtin_trap();
  }
  for (const std::string& host : network.allowed_hosts) {
    if (!strata::auth::is_valid_host_pattern(host))
      __builtin_trap();
  }
}

/// The application main() builds, made once: 50 options take 2 ms to declare under the sanitizers, ten
/// times what a parse takes. Before each input its results are cleared (CLI::App::clear, meant for parsing
/// again) and the options go back to their defaults.
struct Application {
  CLI::App app{"Strata", "strata"};
  strata::app::ServeOptions options;
  Application() {
    static_cast<void>(strata::app::add_serve_command(app, options));
    strata::app::allow_config_file(app);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Application application;
  application.app.clear();
  application.options = strata::app::ServeOptions{};
  std::istringstream file(std::string(reinterpret_cast<const char*>(data), size));
  try {
    // The file as `strata --config FILE serve` reads it; its [serve] section selects the subcommand.
    strata::app::parse_options([&] { application.app.parse_from_stream(file); });
  } catch (const CLI::ParseError&) {
    return 0;
  }
  check(application.options);
  return 0;
}

#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace strata::app {

struct ServeOptions {
  std::string bind_address = "0.0.0.0";
  std::uint16_t port = 8080;
  std::filesystem::path web_root;  ///< empty: the bundle next to the executable
  double pose_rate = 25.0;         ///< Hz
  std::uint64_t seed = 1;
  double time_scale = 1.0;
  int io_threads = 2;
};

/// Runs the server with the simulated robot until SIGINT or SIGTERM. Returns the process exit code.
int serve(const ServeOptions& options);

/// Where the web bundle is when none is given: `web/` next to the executable (a build tree), or
/// `../share/strata/web` from it (an installed package).
[[nodiscard]] std::filesystem::path default_web_root();

}  // namespace strata::app

#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace strata::app {

struct RegisterOptions {
  std::string source;
  std::string target;
  std::string guess;  ///< x,y,z[,roll,pitch,yaw] (metres, degrees); empty: identity
  bool json = false;
};

/// Adds `strata register SOURCE TARGET [--guess ...] [--json]` to `app`, filling `options`.
CLI::App* add_register_command(CLI::App& app, RegisterOptions& options);

/// Registers SOURCE onto TARGET and prints the transform, RMSE, pairs, iterations, verdict and time.
/// Returns the exit code: 0 accepted, 3 rejected by fault control (the numbers are printed either way).
int run_register(const RegisterOptions& options);

}  // namespace strata::app

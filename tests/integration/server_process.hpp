#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::testing {

/// The real strata binary, started with `serve` on a free loopback port and stopped with SIGTERM.
class ServerProcess {
 public:
  explicit ServerProcess(std::vector<std::string> extra_args = {});
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// Sends SIGTERM and waits; returns the exit status (or 128 + signal).
  int stop();

 private:
  pid_t pid_ = -1;
  std::uint16_t port_ = 0;
};

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};
/// Runs the strata binary with `args` to completion (bounded by `timeout`), capturing its output.
CommandResult run_strata(const std::vector<std::string>& args,
                         std::chrono::seconds timeout = std::chrono::seconds(30));

}  // namespace strata::testing

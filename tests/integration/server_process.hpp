#pragma once

#include <sys/resource.h>
#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace strata::testing {

/// The operator token the test servers are started with.
inline constexpr const char* kTestOperatorToken = "integration-test-operator-token";

/// A file system of `bytes` (a tmpfs) mounted at `mount_point` for the server alone: a disk that really fills
/// up (ENOSPC), without root. The server gets a user and a mount namespace of its own (as `unshare -m -U`,
/// its user id mapped to itself, not to root as `unshare -r` would), so the mount is seen by it only and
/// goes away with it; the test reaches the files through ServerProcess::seen_by_server. `mount_point` must
/// be an existing directory.
struct SmallDisk {
  std::filesystem::path mount_point;
  std::uint64_t bytes = 0;
};

/// Resource limits for a server process (setrlimit in the child), and where its log goes.
struct ProcessLimits {
  std::uint64_t file_size = RLIM_INFINITY;   ///< RLIMIT_FSIZE, bytes: a disk that fills up
  std::uint64_t open_files = RLIM_INFINITY;  ///< RLIMIT_NOFILE: a server that runs out of descriptors
  std::uint64_t stack = RLIM_INFINITY;       ///< RLIMIT_STACK, bytes: every thread's stack (glibc)
  std::filesystem::path log_file;            ///< stderr (the log) goes here; empty: to the test's output
  std::optional<SmallDisk> small_disk;       ///< a small file system of the server's own
};

/// Why a server cannot be given a SmallDisk on this machine (user namespaces off, a seccomp filter that
/// refuses unshare or mount, ...), found by trying it in a child process; empty when it can.
std::string small_disk_unavailable();

/// The real strata binary, started with `serve` on a free loopback port and stopped with SIGTERM.
class ServerProcess {
 public:
  explicit ServerProcess(std::vector<std::string> extra_args = {});
  /// `file_size_limit` (bytes) becomes the process's RLIMIT_FSIZE: a disk that fills up.
  ServerProcess(std::vector<std::string> extra_args, std::uint64_t file_size_limit);
  ServerProcess(std::vector<std::string> extra_args, const ProcessLimits& limits);
  /// Stops a server still running (SIGTERM) and fails the running test (gtest's ADD_FAILURE) unless it exits
  /// with status 0.
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// What the server announced it serves: "http", or "https" with TLS.
  [[nodiscard]] const std::string& scheme() const { return scheme_; }
  [[nodiscard]] pid_t pid() const { return pid_; }
  /// The process's resident memory (VmRSS), KiB.
  [[nodiscard]] long resident_kib() const;
  /// Sends SIGTERM and waits; returns the exit status (or 128 + signal), for the caller to check.
  [[nodiscard]] int stop();
  /// Sends SIGKILL (no chance to clean up, as a power cut or the OOM killer) and waits.
  void kill_now();
  /// Stops every thread of the server (SIGSTOP) and waits until they are stopped: until resume() or
  /// kill_now() nothing it does changes, so what a test sees of its files then is what a kill leaves.
  void pause();
  /// Lets a paused server run again (SIGCONT).
  void resume();
  /// `path` as the server sees it, for the test to read and write: through /proc/PID/root, which
  /// resolves paths in the server's mount namespace (a SmallDisk is mounted there only). Valid while the
  /// server runs.
  [[nodiscard]] std::filesystem::path seen_by_server(const std::filesystem::path& path) const;

 private:
  pid_t pid_ = -1;
  std::uint16_t port_ = 0;
  std::string scheme_;
};

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};
/// Runs the strata binary with `args` to completion (bounded by `timeout`), capturing its output.
CommandResult run_strata(const std::vector<std::string>& args,
                         std::chrono::seconds timeout = std::chrono::seconds(30));

/// The JSON object a command printed (`--json`): from its first '{' to its last '}'; empty if none.
inline nlohmann::json json_of(const CommandResult& result) {
  const std::size_t begin = result.output.find('{');
  const std::size_t end = result.output.rfind('}');
  if (begin == std::string::npos || end == std::string::npos)
    return {};
  return nlohmann::json::parse(result.output.substr(begin, end - begin + 1));
}

/// The third-party data directory: STRATA_DATA_DIR from the environment, else the build's setting.
inline std::filesystem::path data_dir() {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  return from_env != nullptr ? std::filesystem::path(from_env) : std::filesystem::path(STRATA_DATA_DIR);
}

/// A file name in the temporary directory that no other test process uses: ctest runs a suite's tests as
/// parallel processes, and a fixed name shared by two of them is removed under the other's feet.
inline std::filesystem::path private_temp_path(const std::string& stem, const std::string& extension) {
  return std::filesystem::temp_directory_path() / (stem + "-" + std::to_string(::getpid()) + extension);
}

/// A file's bytes; empty when it cannot be read.
inline std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace strata::testing

#include "integration/server_process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <utility>

namespace strata::testing {
namespace {

using Clock = std::chrono::steady_clock;

/// The servers' XDG_STATE_HOME (where the IMU calibration is kept between runs): one per test process, so
/// that what one test's robot learnt is not where another test's starts from. Removed at exit.
struct PrivateStateHome {
  std::filesystem::path path = private_temp_path("strata-state", "");
  ~PrivateStateHome() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

/// The environment with XDG_STATE_HOME replaced: built before fork(), as the child may only exec.
std::vector<std::string> child_environment() {
  static const PrivateStateHome state_home;
  std::vector<std::string> environment;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    if (!std::string_view(*entry).starts_with("XDG_STATE_HOME="))
      environment.emplace_back(*entry);
  }
  environment.push_back("XDG_STATE_HOME=" + state_home.path.string());
  return environment;
}

/// What a child needs to mount a SmallDisk in namespaces of its own, prepared before fork(): the child of
/// a threaded process may only make system calls.
struct SmallDiskSetup {
  std::string uid_map;  ///< "UID UID 1": the server runs as the same user inside, not as root
  std::string gid_map;
  std::string mount_point;
  std::string options;  ///< "size=BYTES"
};

SmallDiskSetup prepare_small_disk(const SmallDisk& disk) {
  return {std::to_string(::getuid()) + " " + std::to_string(::getuid()) + " 1",
          std::to_string(::getgid()) + " " + std::to_string(::getgid()) + " 1", disk.mount_point.string(),
          "size=" + std::to_string(disk.bytes)};
}

/// The steps of enter_small_disk, to say which failed.
constexpr std::array<const char*, 6> kSmallDiskSteps{"unshare(CLONE_NEWUSER | CLONE_NEWNS)",
                                                     "write /proc/self/setgroups",
                                                     "write /proc/self/uid_map",
                                                     "write /proc/self/gid_map",
                                                     "make the mounts private",
                                                     "mount a tmpfs"};

bool write_proc_file(const char* path, const std::string& text) {
  const int fd = ::open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0)
    return false;
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const int error = errno;  // the write's, not close's
  ::close(fd);
  errno = error;
  return written;
}

/// In a forked child: a user and a mount namespace of its own, with the tmpfs mounted. -1 when done, else
/// the index in kSmallDiskSteps of the step that failed (errno says why). System calls only.
int enter_small_disk(const SmallDiskSetup& setup) {
  // A new user namespace gives the capabilities to mount in the new mount namespace it owns, without root.
  if (::unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0)
    return 0;
  // An unprivileged process may write its gid_map only once setgroups is denied (absent before Linux 3.19).
  if (!write_proc_file("/proc/self/setgroups", "deny") && errno != ENOENT)
    return 1;
  if (!write_proc_file("/proc/self/uid_map", setup.uid_map))
    return 2;
  if (!write_proc_file("/proc/self/gid_map", setup.gid_map))
    return 3;
  // Mounts made here must not propagate to the namespace the test runs in.
  if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
    return 4;
  if (::mount("tmpfs", setup.mount_point.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, setup.options.c_str()) != 0)
    return 5;
  return -1;
}

/// `value` (at least 0) in decimal into `out` (room for 12 characters): std::to_string may allocate, which
/// the child of a threaded process must not.
std::size_t decimal(int value, char* out) {
  char reversed[12];
  std::size_t n = 0;
  do {
    reversed[n++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value > 0);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = reversed[n - 1 - i];
  return n;
}

pid_t spawn(const std::vector<std::string>& args, int stdout_fd, int stderr_fd,
            const ProcessLimits& limits = {}) {
  // STRATA_SERVER_BINARY: another build's binary, for a benchmark's "before" figures.
  const char* other_binary = std::getenv("STRATA_SERVER_BINARY");
  std::vector<std::string> argv_storage{other_binary != nullptr ? other_binary : STRATA_BINARY};
  argv_storage.insert(argv_storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& arg : argv_storage)
    argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::vector<std::string> environment = child_environment();
  std::vector<char*> envp;
  for (auto& entry : environment)
    envp.push_back(entry.data());
  envp.push_back(nullptr);
  const std::optional<SmallDiskSetup> small_disk =
      limits.small_disk ? std::optional(prepare_small_disk(*limits.small_disk)) : std::nullopt;
  const pid_t pid = fork();
  if (pid < 0)
    throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    dup2(stdout_fd, STDOUT_FILENO);
    if (stderr_fd >= 0)
      dup2(stderr_fd, STDERR_FILENO);
    if (small_disk) {
      if (const int step = enter_small_disk(*small_disk); step >= 0) {
        // On stdout, where ServerProcess waits for the server's first line and shows what came instead.
        const int error = errno;
        constexpr std::string_view kWhat = "small disk: cannot ";
        char number[12];
        [[maybe_unused]] ssize_t ignored = ::write(STDOUT_FILENO, kWhat.data(), kWhat.size());
        ignored = ::write(STDOUT_FILENO, kSmallDiskSteps[step], std::strlen(kSmallDiskSteps[step]));
        ignored = ::write(STDOUT_FILENO, ", errno ", 8);
        ignored = ::write(STDOUT_FILENO, number, decimal(error, number));
        _exit(126);
      }
    }
    if (limits.file_size != RLIM_INFINITY) {
      const rlimit limit{limits.file_size, limits.file_size};
      setrlimit(RLIMIT_FSIZE, &limit);
    }
    if (limits.open_files != RLIM_INFINITY) {
      const rlimit limit{limits.open_files, limits.open_files};
      setrlimit(RLIMIT_NOFILE, &limit);
    }
    if (limits.stack != RLIM_INFINITY) {  // glibc sizes new threads' stacks by it too
      const rlimit limit{limits.stack, limits.stack};
      setrlimit(RLIMIT_STACK, &limit);
    }
    execve(argv[0], argv.data(), envp.data());
    _exit(127);
  }
  return pid;
}

int exit_status(int status) {
  if (WIFEXITED(status))
    return WEXITSTATUS(status);
  if (WIFSIGNALED(status))
    return 128 + WTERMSIG(status);
  return -1;
}

// Reads what is available from `fd` into `out` until `deadline`; false at EOF or timeout.
bool read_some(int fd, std::string& out, Clock::time_point deadline) {
  const auto remaining = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  if (remaining.count() <= 0)
    return false;
  pollfd pfd{fd, POLLIN, 0};
  if (poll(&pfd, 1, static_cast<int>(remaining.count())) <= 0)
    return false;
  char buffer[4096];
  const ssize_t n = read(fd, buffer, sizeof buffer);
  if (n <= 0)
    return false;
  out.append(buffer, static_cast<std::size_t>(n));
  return true;
}

}  // namespace

ServerProcess::ServerProcess(std::vector<std::string> extra_args)
    : ServerProcess(std::move(extra_args), RLIM_INFINITY) {}

ServerProcess::ServerProcess(std::vector<std::string> extra_args, std::uint64_t file_size_limit)
    : ServerProcess(std::move(extra_args), ProcessLimits{.file_size = file_size_limit}) {}

ServerProcess::ServerProcess(std::vector<std::string> extra_args, const ProcessLimits& limits) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe failed");
  std::vector<std::string> args{"serve", "--bind",           "127.0.0.1",       "--port",
                                "0",     "--operator-token", kTestOperatorToken};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  // stderr (the log) goes to the test's output, or to the log file asked for.
  int log_fd = -1;
  if (!limits.log_file.empty()) {
    log_fd = open(limits.log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log_fd < 0)
      throw std::runtime_error("cannot create " + limits.log_file.string());
  }
  pid_ = spawn(args, pipe_fds[1], log_fd, limits);
  close(pipe_fds[1]);
  if (log_fd >= 0)
    close(log_fd);

  // The server prints one line on stdout once it listens; wait for it and read the real port.
  const std::regex serving(R"(strata: serving on (https?)://127\.0\.0\.1:(\d+))");
  std::string output;
  std::smatch match;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (!std::regex_search(output, match, serving)) {
    if (!read_some(pipe_fds[0], output, deadline)) {
      close(pipe_fds[0]);
      const int status = stop();
      throw std::runtime_error("strata did not start serving (exit status " + std::to_string(status) +
                               "); stdout was: " + output);
    }
  }
  close(pipe_fds[0]);  // nothing else is printed on stdout
  scheme_ = match[1];
  port_ = static_cast<std::uint16_t>(std::stoi(match[2]));
}

long ServerProcess::resident_kib() const {
  std::ifstream status("/proc/" + std::to_string(pid_) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.starts_with("VmRSS:"))
      return std::stol(line.substr(6));
  }
  return -1;
}

ServerProcess::~ServerProcess() {
  if (pid_ <= 0)
    return;  // stopped or killed by the test, which saw the status
  // A test that leaves the server to its fixture still has it checked: a crash, a hang broken by the
  // timeout or a sanitizer's report at shutdown (an ASan leak exits 1) must fail the test that ran it.
  const pid_t pid = pid_;
  if (const int status = stop(); status != 0) {
    ADD_FAILURE() << "strata (pid " << pid << ") exited with status " << status
                  << " on SIGTERM, not 0: a crash, or a sanitizer's report at shutdown (see its log above)";
  }
}

int ServerProcess::stop() {
  if (pid_ <= 0)
    return -1;
  kill(pid_, SIGTERM);
  kill(pid_, SIGCONT);  // a paused server (a test that failed between pause() and kill_now()) must run to end
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return exit_status(status);
}

void ServerProcess::kill_now() {
  if (pid_ <= 0)
    return;
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

void ServerProcess::pause() {
  if (pid_ <= 0)
    throw std::runtime_error("pause: the server is not running");
  kill(pid_, SIGSTOP);
  int status = 0;
  waitpid(pid_, &status, WUNTRACED);  // reported once every thread has stopped
  if (!WIFSTOPPED(status)) {
    pid_ = -1;
    throw std::runtime_error("pause: the server ended, status " + std::to_string(exit_status(status)));
  }
}

void ServerProcess::resume() {
  if (pid_ > 0)
    kill(pid_, SIGCONT);
}

std::filesystem::path ServerProcess::seen_by_server(const std::filesystem::path& path) const {
  return std::filesystem::path("/proc/" + std::to_string(pid_) + "/root") /
         std::filesystem::absolute(path).relative_path();
}

std::string small_disk_unavailable() {
  const std::filesystem::path mount_point = private_temp_path("strata-small-disk-probe", "");
  std::filesystem::create_directories(mount_point);
  const SmallDiskSetup setup = prepare_small_disk({mount_point, 64 * 1024});
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid < 0)
    throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {  // tries in a child: the namespaces and the mount go away with it
    const int step = enter_small_disk(setup);
    const std::array<int, 2> outcome{step, errno};
    [[maybe_unused]] const ssize_t ignored = ::write(pipe_fds[1], outcome.data(), sizeof outcome);
    _exit(0);
  }
  close(pipe_fds[1]);
  std::array<int, 2> outcome{0, 0};
  const bool reported = read(pipe_fds[0], outcome.data(), sizeof outcome) == sizeof outcome;
  close(pipe_fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  std::error_code ignored;
  std::filesystem::remove(mount_point, ignored);
  if (!reported)
    return "the probe process ended without saying";
  if (outcome[0] < 0)
    return {};
  return std::string("cannot ") + kSmallDiskSteps[static_cast<std::size_t>(outcome[0])] + ": " +
         std::strerror(outcome[1]);
}

CommandResult run_strata(const std::vector<std::string>& args, std::chrono::seconds timeout) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0)
    throw std::runtime_error("pipe failed");
  const pid_t pid = spawn(args, pipe_fds[1], pipe_fds[1]);
  close(pipe_fds[1]);
  CommandResult result;
  const auto deadline = Clock::now() + timeout;
  while (read_some(pipe_fds[0], result.output, deadline)) {
  }
  close(pipe_fds[0]);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (Clock::now() > deadline) {
      kill(pid, SIGKILL);  // over its time: a hang shows up as exit code 137
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  result.exit_code = exit_status(status);
  return result;
}

}  // namespace strata::testing

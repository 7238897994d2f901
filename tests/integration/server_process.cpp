#include "integration/server_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

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
  const pid_t pid = fork();
  if (pid < 0)
    throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    dup2(stdout_fd, STDOUT_FILENO);
    if (stderr_fd >= 0)
      dup2(stderr_fd, STDERR_FILENO);
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
      stop();
      throw std::runtime_error("strata did not start serving; stdout was: " + output);
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
  stop();
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

// Faults while the real server saves its map (issue #10): the process killed at varied points during saves,
// and a disk that fills up. The map file must always load as the previous map or the new one, never be
// half written, and no temporary file may take its place.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/http.hpp>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr const char* kMapName = "site.strata";

std::vector<std::string> server_args(const fs::path& maps_dir, int seed) {
  return {"--world", "yard",   "--scanner",          "tilting",    "--time-scale",
          "4",       "--seed", std::to_string(seed), "--maps-dir", maps_dir.string()};
}

/// Waits until the live map covers `tiles` tiles, so a save writes a real map.
void wait_for_map(std::uint16_t port, std::uint64_t tiles = 1) {
  const auto deadline = std::chrono::steady_clock::now() + 120s;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto status = nlohmann::json::parse(http_get(port, "/api/v1/status").body());
    if (status["map"]["tiles"].get<std::uint64_t>() >= tiles)
      return;
    std::this_thread::sleep_for(50ms);
  }
  throw std::runtime_error("the live map stayed empty");
}

http::response<http::string_body> save(std::uint16_t port) {
  return http_request(port, http::verb::post, "/api/v1/maps", nlohmann::json{{"name", kMapName}}.dump(),
                      kTestOperatorToken);
}

/// Whether `strata map export` (the real loader, every check of the format) loads the map file; else why not.
/// The PLY goes to a file of this test's own: not /dev/null, which the export, run as root, replaced.
std::string load_problem(const fs::path& file) {
  const fs::path ply = private_temp_path("strata-save-faults-export", ".ply");
  const CommandResult result = run_strata({"map", "export", file.string(), "--ply", ply.string()});
  fs::remove(ply);
  return result.exit_code == 0 ? std::string() : result.output;
}

/// Files in the maps directory other than the map itself: what a killed save left behind.
/// The maps directory's files but the map and the map server's versions (.versions: every save is one too;
/// tests/unit/server/pipeline/map_versions_test.cpp).
std::vector<std::string> other_files(const fs::path& maps_dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(maps_dir)) {
    if (entry.path().filename() != kMapName && entry.path().filename() != ".versions")
      names.push_back(entry.path().filename().string());
  }
  return names;
}

/// A fresh maps directory, removed at the end.
class SaveFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    maps_dir_ = fs::temp_directory_path() / ("strata-save-faults-" + std::to_string(::getpid()) + "-" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(maps_dir_);
    fs::create_directories(maps_dir_);
  }
  void TearDown() override { fs::remove_all(maps_dir_); }

  /// One complete save by a server: the map every later fault must keep or replace whole.
  void save_a_first_map() {
    ServerProcess server(server_args(maps_dir_, 1));
    wait_for_map(server.port());
    ASSERT_EQ(save(server.port()).result(), http::status::created);
    ASSERT_EQ(load_problem(maps_dir_ / kMapName), "");
  }

  fs::path maps_dir_;
};

/// What happens to the map in the maps directory, from inotify: how often a save's temporary was created
/// (a save began writing) and the map replaced by a rename (a save committed). The kernel queues an event
/// within the system call that causes it, so with the server paused or dead the counts are exact once the
/// queue is read.
class MapsDirectoryWatch {
 public:
  MapsDirectoryWatch(const fs::path& directory, std::string temporary_name)
      : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)), temporary_name_(std::move(temporary_name)) {
    if (fd_ < 0 || ::inotify_add_watch(fd_, directory.c_str(), IN_CREATE | IN_MOVED_TO) < 0)
      throw std::runtime_error("inotify on " + directory.string() + ": " + std::strerror(errno));
  }
  ~MapsDirectoryWatch() { ::close(fd_); }
  MapsDirectoryWatch(const MapsDirectoryWatch&) = delete;
  MapsDirectoryWatch& operator=(const MapsDirectoryWatch&) = delete;

  [[nodiscard]] int created() const { return created_; }
  [[nodiscard]] int replaced() const { return replaced_; }

  /// Reads every queued event, waiting at most `timeout` for the first; false if none came.
  bool read(std::chrono::milliseconds timeout) {
    pollfd ready{fd_, POLLIN, 0};
    if (::poll(&ready, 1, static_cast<int>(timeout.count())) <= 0)
      return false;
    alignas(inotify_event) char buffer[4096];
    for (ssize_t length; (length = ::read(fd_, buffer, sizeof buffer)) > 0;) {
      for (ssize_t at = 0; at < length;) {
        const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
        const std::string name = event->len > 0 ? event->name : "";
        if ((event->mask & IN_CREATE) != 0 && name == temporary_name_)
          ++created_;
        else if ((event->mask & IN_MOVED_TO) != 0 && name == kMapName)
          ++replaced_;
        at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
      }
    }
    return true;
  }

  /// Reads events until `done()`; throws when a minute passes without one (the saves stopped).
  template <class Condition>
  void read_until(Condition done) {
    while (!done()) {
      if (!read(std::chrono::milliseconds(60000)))
        throw std::runtime_error("no save wrote its file in 60 s");
    }
  }

 private:
  int fd_;
  std::string temporary_name_;
  int created_ = 0;
  int replaced_ = 0;
};

/// How many saves the server's log says ended ("map saved to", "map save failed"): a save logs it before it
/// returns, to stderr, which is unbuffered, so with the server paused or dead the count is exact.
int saves_ended(const fs::path& log) {
  std::ifstream in(log);
  int ended = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.find("map saved to ") != std::string::npos || line.find("map save failed") != std::string::npos)
      ++ended;
  }
  return ended;
}

/// Sends a save of the map on a connection of its own, whose answer is never read.
tcp::socket send_save(boost::asio::io_context& io, std::uint16_t port) {
  tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  http::request<http::string_body> request{http::verb::post, "/api/v1/maps", 11};
  request.set(http::field::host, "127.0.0.1");
  request.set(http::field::authorization, std::string("Bearer ") + kTestOperatorToken);
  request.body() = nlohmann::json{{"name", kMapName}}.dump();
  request.prepare_payload();
  http::write(socket, request);
  return socket;
}

// STRATA_SAVE_KILLS sets the number of kills (default 20; README: the 100-kill run).
//
// Each kill is aimed inside a save by construction, not by luck: when a save's temporary appears the server
// is paused (SIGSTOP, every thread) after a delay, and killed if that save has not ended yet (its "map saved"
// line is not in the log); when it ended first, the server runs on and the next save is paused at once. A
// paused server changes nothing, so the kill lands exactly where the pause did: after the temporary's
// creation and before the save returned (before or after its rename). Whatever the timing, the verdict is
// read afterwards, never assumed: from the files, the inotify queue and the log, all complete once the
// server is dead. A kill left the temporary behind (SIGKILL leaves no chance to remove it) when it came
// before the rename; the map must be the previous file byte for byte unless a save of this round renamed.
TEST_F(SaveFaults, KilledDuringSavesTheMapFileIsThePreviousOrTheNewMap) {
  const char* from_env = std::getenv("STRATA_SAVE_KILLS");
  const int kills = from_env != nullptr ? std::atoi(from_env) : 20;
  constexpr int kMostSavesPerRound = 8;  // tries for a save the pause comes too late for
  save_a_first_map();
  const fs::path file = maps_dir_ / kMapName;
  const fs::path log = private_temp_path("strata-save-kill", ".log");
  int previous = 0;
  int replaced = 0;
  int corrupt = 0;
  int before_writing = 0;  // kills inside a save that left its temporary empty
  int before_rename = 0;   // left it written, not renamed
  int after_rename = 0;    // came after the rename, before the save returned (the directory's fsync)
  for (int round = 0; round < kills; ++round) {
    const std::string before = file_bytes(file);
    ServerProcess server(server_args(maps_dir_, 2 + round), ProcessLimits{.log_file = log});  // another map
    // What the last kill left, this server removed as it started (AServerRemovesWhatKilledSavesLeft).
    EXPECT_TRUE(other_files(maps_dir_).empty()) << "round " << round;
    const std::string temporary = std::string(kMapName) + ".tmp." + std::to_string(server.pid());
    MapsDirectoryWatch watch(maps_dir_, temporary);
    wait_for_map(server.port());
    boost::asio::io_context io;
    std::vector<tcp::socket> requests;
    // Every other round lets one save commit first: the file is then a new map. The delay after the aimed
    // save's temporary appears walks 0-1.8 ms in steps of 0.2 ms every two rounds, through the write, the
    // fsync (1-30 ms on a disk, nothing on tmpfs), the rename and the directory's fsync.
    if (round % 2 == 1) {
      requests.push_back(send_save(io, server.port()));
      watch.read_until([&] { return watch.replaced() == 1; });
    }
    std::chrono::microseconds delay((round / 2 % 10) * 200);
    for (int attempt = 0; attempt < kMostSavesPerRound; ++attempt) {
      requests.push_back(send_save(io, server.port()));
      const int aimed = watch.created() + 1;
      watch.read_until([&] { return watch.created() >= aimed; });
      std::this_thread::sleep_for(delay);
      server.pause();
      watch.read(0ms);
      if (watch.created() > saves_ended(log))
        break;  // paused inside a save: the kill lands there
      server.resume();
      delay = std::chrono::microseconds(0);  // this save ended first; the next one at once
    }
    server.kill_now();  // when every try came too late: after the last save

    // The verdict, from what the server left.
    watch.read(0ms);
    const bool inside = watch.created() > saves_ended(log);
    const bool temporary_left = fs::exists(maps_dir_ / temporary);
    if (temporary_left)
      ++(fs::file_size(maps_dir_ / temporary) == 0 ? before_writing : before_rename);
    else if (inside)
      ++after_rename;
    EXPECT_TRUE(inside || !temporary_left) << "round " << round << ": a temporary, no save under way";
    // The two markers agree: every save that renamed logged its end, but one killed between the two.
    EXPECT_EQ(watch.replaced(), saves_ended(log) + (inside && !temporary_left ? 1 : 0)) << "round " << round;
    const std::string problem = load_problem(file);
    const std::string after = file_bytes(file);
    if (!problem.empty()) {
      ++corrupt;
      ADD_FAILURE() << "round " << round << ": " << problem;
    } else if (after == before) {
      ++previous;
    } else {
      ++replaced;
    }
    // No save of this round renamed: the previous map, byte for byte; else a new one (another seed's).
    if (watch.replaced() == 0)
      EXPECT_TRUE(after == before) << "round " << round << ": the map changed, no save renamed";
    else
      EXPECT_FALSE(after == before) << "round " << round << ": " << watch.replaced() << " saves renamed";
    // Beside the map, only the killed save's own temporary (name.tmp.PID, never listed or loaded).
    EXPECT_EQ(other_files(maps_dir_),
              temporary_left ? std::vector<std::string>{temporary} : std::vector<std::string>{})
        << "round " << round;
  }
  fs::remove(log);
  const int inside = before_writing + before_rename + after_rename;
  std::cout << "kill-during-save: " << kills << " kills, " << inside << " inside a save (" << before_writing
            << " before its write, " << before_rename << " before its rename, " << after_rename
            << " after); the map file: " << previous << " previous, " << replaced << " new, " << corrupt
            << " corrupt\n";
  EXPECT_EQ(corrupt, 0);
  // The construction lands nearly every kill inside a save: all 20 when measured with the maps on a disk
  // (where fsync keeps a save open for milliseconds) and on tmpfs (where its write takes microseconds). A
  // kill misses only when all kMostSavesPerRound saves of a round ended before the pause. Half leaves
  // room for a loaded machine and still fails a schedule that kills outside saves (the sleeps this test
  // used before left 0 of 20 kills inside a save on tmpfs).
  EXPECT_GE(inside, (kills + 1) / 2) << "too few kills landed inside a save";

  // The server itself, started on what the kills left, lists only the map and loads it.
  ServerProcess server(server_args(maps_dir_, 1));
  const auto list = nlohmann::json::parse(
      http_request(server.port(), http::verb::get, "/api/v1/maps", {}, kTestOperatorToken).body());
  ASSERT_EQ(list["maps"].size(), 1U) << list.dump();
  EXPECT_EQ(list["maps"][0]["name"], kMapName);
  const auto loaded = http_request(server.port(), http::verb::post,
                                   std::string("/api/v1/maps/") + kMapName + "/load", {}, kTestOperatorToken);
  EXPECT_EQ(loaded.result(), http::status::ok) << loaded.body();
}

/// The id of a process that has ended: what a save killed by a power cut leaves in its temporary's name.
pid_t ended_process() {
  const pid_t child = ::fork();
  if (child == 0)
    ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST_F(SaveFaults, AServerRemovesWhatKilledSavesLeftAndNothingElse) {
  const std::string dead = std::to_string(ended_process());
  const auto write = [this](const std::string& name) { std::ofstream(maps_dir_ / name) << "bytes"; };
  // Left by killed saves: removed.
  write(std::string(kMapName) + ".tmp." + dead);
  write("other map.tmp." + dead);
  // Not ours, or not stale: kept. A running process's temporary (this test's own pid: a save under way in
  // another server), files that only look similar, a directory and a link with the temporaries' name.
  const std::vector<std::string> kept{"site.strata",
                                      "running.strata.tmp." + std::to_string(::getpid()),
                                      "notes.tmp",
                                      "data.tmp.12ab",
                                      "data.tmp.",
                                      ".tmp." + dead,
                                      "trailing.tmp." + dead + ".bak"};
  for (const auto& name : kept)
    write(name);
  fs::create_directory(maps_dir_ / ("folder.tmp." + dead));
  fs::create_symlink(maps_dir_ / "site.strata", maps_dir_ / ("link.tmp." + dead));

  ServerProcess server(server_args(maps_dir_, 1));
  std::vector<std::string> left = other_files(maps_dir_);
  left.push_back(kMapName);
  std::sort(left.begin(), left.end());
  std::vector<std::string> expected = kept;
  expected.push_back("folder.tmp." + dead);
  expected.push_back("link.tmp." + dead);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(left, expected);
  // A map may not be saved under such a name: the next start could take it for a leftover.
  const auto refused = http_request(server.port(), http::verb::post, "/api/v1/maps",
                                    nlohmann::json{{"name", "x.tmp.1"}}.dump(), kTestOperatorToken);
  EXPECT_EQ(refused.result(), http::status::bad_request) << refused.body();
}

// A file too large, without root: the server runs with a file size limit (RLIMIT_FSIZE) smaller than its map:
// EFBIG, the write refused as on a full disk, where no namespaces can be had (NoSpaceLeft... skips there).
TEST_F(SaveFaults, DiskFullTheSaveFailsWithIoErrorAndThePreviousMapStays) {
  save_a_first_map();
  const fs::path file = maps_dir_ / kMapName;
  const std::string before = file_bytes(file);
  ServerProcess server(server_args(maps_dir_, 2), /*file_size_limit=*/4096);
  wait_for_map(server.port(), 8);  // a tile takes over 1 KiB in the file
  const auto answer = save(server.port());
  EXPECT_EQ(answer.result(), http::status::internal_server_error) << answer.body();
  const auto body = nlohmann::json::parse(answer.body());
  EXPECT_EQ(body["error"]["code"], "io_error") << answer.body();
  const std::string message = body["error"]["message"];
  EXPECT_NE(message.find("File too large"), std::string::npos) << answer.body();
  // Where the server keeps its files and its process id are not a client's business (issue 59 item 9).
  EXPECT_EQ(message.find(maps_dir_.string()), std::string::npos) << message;
  EXPECT_EQ(message.find(".tmp." + std::to_string(server.pid())), std::string::npos) << message;
  EXPECT_NE(message.find(kMapName), std::string::npos) << "the file is named: " << message;
  EXPECT_EQ(file_bytes(file), before);          // the previous map, byte for byte
  EXPECT_TRUE(other_files(maps_dir_).empty());  // the failed save removed its temporary
  // The server is still up and serving.
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);
}

/// Writes zeros to `path` until the file system is full or `most` bytes are written; the errno that stopped
/// it (ENOSPC on a full disk), or 0. `most` keeps a test whose small disk is not mounted from filling a
/// real one.
int fill_up(const fs::path& path, std::uint64_t most) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    return errno;
  const std::string zeros(64 * 1024, '\0');
  int error = 0;
  for (std::uint64_t written = 0; written < most && error == 0;) {
    const ssize_t n = ::write(fd, zeros.data(), zeros.size());
    if (n < 0)
      error = errno;
    else
      written += static_cast<std::uint64_t>(n);
  }
  ::close(fd);
  return error;
}

// A full disk for real: the server's maps directory is a tmpfs of its own (SmallDisk, 8 MiB), filled up
// by the test, so that writing the map fails with ENOSPC. Then space is freed and a save goes through.
TEST_F(SaveFaults, NoSpaceLeftTheSaveFailsWithIoErrorThePreviousMapStaysAndALaterSaveWorks) {
  if (const std::string why = small_disk_unavailable(); !why.empty()) {
    GTEST_SKIP() << "no small file system of the server's own to fill up (" << why
                 << "): it takes unprivileged user and mount namespaces. The RLIMIT_FSIZE test still runs.";
  }
  constexpr std::uint64_t kDiskBytes = 8 << 20;  // room for two maps of a few minutes' mapping
  ServerProcess server(server_args(maps_dir_, 1),
                       ProcessLimits{.small_disk = SmallDisk{maps_dir_, kDiskBytes}});
  const fs::path maps = server.seen_by_server(maps_dir_);
  const fs::path file = maps / kMapName;
  wait_for_map(server.port());
  ASSERT_EQ(save(server.port()).result(), http::status::created);
  const std::string before = file_bytes(file);
  ASSERT_EQ(load_problem(file), "");
  EXPECT_TRUE(fs::is_empty(maps_dir_)) << "the small disk is the server's alone, not in the test's view";
  ASSERT_EQ(fill_up(maps / "filler", kDiskBytes), ENOSPC) << "the small disk did not fill up";

  const auto answer = save(server.port());
  ASSERT_EQ(answer.result(), http::status::internal_server_error) << answer.body();
  const auto body = nlohmann::json::parse(answer.body());
  EXPECT_EQ(body["error"]["code"], "io_error") << answer.body();
  const std::string message = body["error"]["message"];
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << answer.body();
  EXPECT_NE(message.find(kMapName), std::string::npos) << "the file is named: " << message;
  EXPECT_EQ(message.find(maps_dir_.string()), std::string::npos) << message;
  EXPECT_EQ(message.find(".tmp." + std::to_string(server.pid())), std::string::npos) << message;
  EXPECT_EQ(file_bytes(file), before);                               // the previous map, byte for byte
  EXPECT_EQ(load_problem(file), "");                                 // and it loads
  EXPECT_EQ(other_files(maps), std::vector<std::string>{"filler"});  // the failed save removed its temporary
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);

  // Space again: the next save goes through, whole.
  fs::remove(maps / "filler");
  const auto later = save(server.port());
  EXPECT_EQ(later.result(), http::status::created) << later.body();
  EXPECT_EQ(load_problem(file), "");
  EXPECT_TRUE(other_files(maps).empty());
}

}  // namespace
}  // namespace strata::testing

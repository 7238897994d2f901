#include "core/files/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/files/temporary_files.hpp"

namespace strata {
namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& file, int error) {
  throw FileWriteError("cannot " + what + " " + file.string() + ": " + std::strerror(error));
}

void write_all(int fd, std::string_view data, const std::filesystem::path& file) {
  std::size_t written = 0;
  while (written < data.size()) {
    const ssize_t n = ::write(fd, data.data() + written, data.size() - written);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      fail("write", file, errno);
    }
    written += static_cast<std::size_t>(n);
  }
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view data, Durability durability) {
  // Replacing is for regular files. Renamed over a device or a FIFO, the temporary takes its place: run as
  // root, `strata map export MAP --ply /dev/null` made /dev/null a regular file for the whole machine. (A
  // directory is left to the rename, which fails.)
  struct stat existing {};
  if (::stat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode) && !S_ISDIR(existing.st_mode))
    throw FileWriteError("cannot write " + path.string() + ": not a regular file");
  const std::filesystem::path temporary = temporary_path_for(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    fail("create", temporary, errno);
  try {
    write_all(fd, data, temporary);
    if (durability == Durability::kOnDisk && ::fsync(fd) != 0)
      fail("fsync", temporary, errno);
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::close(fd) != 0) {  // NFS and friends report write errors here
    const int error = errno;
    ::unlink(temporary.c_str());
    fail("write", temporary, error);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    throw FileWriteError("cannot rename " + temporary.string() + " to " + path.string() + ": " +
                         std::strerror(error));
  }
  if (durability == Durability::kOnDisk) {
    // The rename itself is durable only once the directory is on disk.
    std::filesystem::path directory = path.parent_path();
    if (directory.empty())
      directory = ".";
    const int dir_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir_fd >= 0) {
      ::fsync(dir_fd);
      ::close(dir_fd);
    }
  }
}

}  // namespace strata

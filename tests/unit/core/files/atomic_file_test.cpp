#include "core/files/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace strata {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("strata-atomic-file-" + std::to_string(::getpid()));
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }
  fs::path directory_;
};

TEST_F(AtomicFile, ReplacesTheFileWholeAndLeavesNoTemporary) {
  for (const Durability durability : {Durability::kOnDisk, Durability::kOrdered}) {
    const fs::path file = directory_ / "map.smls";
    write_file_atomically(file, "old", durability);
    write_file_atomically(file, std::string(100000, 'n'), durability);
    EXPECT_EQ(read(file), std::string(100000, 'n'));
    EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 1);
  }
}

TEST_F(AtomicFile, AFailedWriteLeavesThePreviousFileAndNamesTheFile) {
  const fs::path file = directory_ / "map.smls";
  write_file_atomically(file, "previous", Durability::kOnDisk);
  // The rename cannot replace a directory: the write fails after the temporary was written.
  const fs::path blocked = directory_ / "blocked";
  fs::create_directories(blocked / "inside");
  try {
    write_file_atomically(blocked, "new", Durability::kOnDisk);
    FAIL() << "no error";
  } catch (const FileWriteError& error) {
    EXPECT_NE(std::string(error.what()).find("blocked"), std::string::npos) << error.what();
  }
  EXPECT_EQ(read(file), "previous");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 2);  // no temporary
  EXPECT_THROW(write_file_atomically(directory_ / "missing" / "x", "x", Durability::kOrdered),
               FileWriteError);
}

// Renamed over a device or a FIFO, the temporary would take its place: `strata map export MAP --ply
// /dev/null` run as root (the save-fault suite's load check did) made /dev/null a regular file for every
// process on the machine. A FIFO stands for the device here: any user can make one.
TEST_F(AtomicFile, RefusesToReplaceWhatIsNotARegularFile) {
  const fs::path pipe = directory_ / "pipe";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0644), 0);
  for (const Durability durability : {Durability::kOnDisk, Durability::kOrdered}) {
    try {
      write_file_atomically(pipe, "data", durability);
      FAIL() << "no error";
    } catch (const FileWriteError& error) {
      EXPECT_NE(std::string(error.what()).find("not a regular file"), std::string::npos) << error.what();
    }
    EXPECT_EQ(fs::symlink_status(pipe).type(), fs::file_type::fifo);
    EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()),
              1);  // no temporary
  }
}

}  // namespace
}  // namespace strata

#include "core/files/atomic_file.hpp"

#include <gtest/gtest.h>
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

}  // namespace
}  // namespace strata

// The MCAP reader on the writer's own files: every message back, with its channel, sequence, time and
// bytes, zstd or not; and a file cut anywhere or damaged in a chunk, the data section or the summary is
// refused with an McapError saying what.
#include "drivers/mcap/mcap_reader.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "drivers/mcap/mcap_writer.hpp"

namespace strata::mcap {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> payload(int i) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(20 + i));
  for (std::size_t k = 0; k < bytes.size(); ++k)
    bytes[k] = static_cast<std::uint8_t>(k * 7 + static_cast<std::size_t>(i));
  return bytes;
}

/// Two channels, 40 messages in several chunks.
std::string written_file(Compression compression) {
  McapWriter writer({.compression = compression, .chunk_size = 300});
  const std::uint16_t schema = writer.add_schema("pkg/msg/A", "ros2msg", "int32 a\n");
  const std::uint16_t a = writer.add_channel(schema, "/a", "cdr");
  const std::uint16_t b = writer.add_channel(0, "/b", "json");
  for (int i = 0; i < 40; ++i)
    writer.add_message(i % 3 == 0 ? b : a, static_cast<std::uint64_t>(1000 + i), 0, payload(i));
  writer.finish();
  return writer.take_output();
}

class McapReaderTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& bytes) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path_;
  }
  /// The McapError's message for `bytes`, or "" when they were read.
  std::string error_for(const std::string& bytes) {
    try {
      const McapReader reader(write(bytes));
    } catch (const McapError& e) {
      return e.what();
    }
    return "";
  }
  void TearDown() override { fs::remove(path_); }

  fs::path path_ = fs::temp_directory_path() / ("strata_mcap_reader_" + std::to_string(::getpid()) + ".mcap");
};

TEST_F(McapReaderTest, ReadsEveryMessageBackZstdOrNot) {
  for (const Compression compression : {Compression::kZstd, Compression::kNone}) {
    McapReader reader(write(written_file(compression)));
    ASSERT_EQ(reader.channels().size(), 2U);
    ASSERT_NE(reader.channel("/a"), nullptr);
    EXPECT_EQ(reader.channel("/a")->schema_name, "pkg/msg/A");
    EXPECT_EQ(reader.channel("/b")->schema_name, "");
    EXPECT_EQ(reader.channel("/b")->message_encoding, "json");
    ASSERT_EQ(reader.messages().size(), 40U);
    std::uint32_t next_a = 0, next_b = 0;
    for (int i = 0; i < 40; ++i) {
      const McapMessage& message = reader.messages()[static_cast<std::size_t>(i)];
      const bool on_b = i % 3 == 0;
      EXPECT_EQ(message.channel_id, on_b ? reader.channel("/b")->id : reader.channel("/a")->id);
      EXPECT_EQ(message.sequence, on_b ? next_b++ : next_a++);
      EXPECT_EQ(message.log_time, static_cast<std::uint64_t>(1000 + i));
      const std::vector<std::uint8_t> expected = payload(i);
      EXPECT_EQ(reader.message_data(message), std::string(expected.begin(), expected.end())) << i;
    }
    EXPECT_GT(reader.messages().back().chunk, 2U);  // several chunks were read
  }
}

TEST_F(McapReaderTest, AFileCutAnywhereIsRefused) {
  const std::string file = written_file(Compression::kZstd);
  for (std::size_t cut = 0; cut < file.size(); cut += 7) {
    const std::string message = error_for(file.substr(0, cut));
    EXPECT_NE(message, "") << "cut at " << cut;
    EXPECT_NE(message.find(cut < 8 ? "not an MCAP file" : "cut short"), std::string::npos)
        << "cut at " << cut << ": " << message;
  }
  EXPECT_NE(error_for(file.substr(0, file.size() - 1)), "");
  EXPECT_EQ(error_for(file), "");
}

TEST_F(McapReaderTest, ADamagedChunkDataSectionOrSummaryIsRefusedByItsCrc) {
  const std::string file = written_file(Compression::kNone);
  // A byte inside the first chunk's records (uncompressed: the chunk's CRC catches it).
  const std::size_t in_chunk = file.find(std::string(reinterpret_cast<const char*>(payload(1).data()), 20));
  ASSERT_NE(in_chunk, std::string::npos);
  std::string damaged = file;
  damaged[in_chunk + 3] ^= 0x10;
  EXPECT_NE(error_for(damaged).find("CRC32"), std::string::npos) << error_for(damaged);
  // A byte of the summary (the last schema record's name, after Data End): the footer's CRC.
  damaged = file;
  const std::size_t in_summary = file.rfind("pkg/msg/A");
  damaged[in_summary] = 'q';
  EXPECT_NE(error_for(damaged).find("summary's CRC32"), std::string::npos) << error_for(damaged);
}

TEST_F(McapReaderTest, NotAnMcapFileAndAnAbsurdLengthAreRefused) {
  EXPECT_NE(error_for("hello, world, not an MCAP file").find("not an MCAP file"), std::string::npos);
  std::string file = written_file(Compression::kZstd);
  // The Header's length (after the magic and opcode) made huge: a cut-short record, nothing allocated.
  for (std::size_t k = 9; k < 17; ++k)
    file[k] = '\x7f';
  EXPECT_NE(error_for(file).find("cut short"), std::string::npos);
}

TEST_F(McapReaderTest, AChunkClaimingMoreThanItsZstdFrameHoldsIsRefusedBeforeItIsAllocated) {
  std::string file = written_file(Compression::kZstd);
  std::size_t offset = 8;  // after the magic: the records, up to the first chunk
  while (static_cast<std::uint8_t>(file[offset]) != 0x06) {
    std::uint64_t length = 0;
    std::memcpy(&length, file.data() + offset + 1, sizeof(length));
    offset += 9 + length;
  }
  const std::uint64_t claim = std::uint64_t{200} << 20;  // its uncompressed size: 200 MiB
  std::memcpy(file.data() + offset + 9 + 16, &claim, sizeof(claim));
  EXPECT_NE(error_for(file).find("not one zstd frame"), std::string::npos) << error_for(file);
}

}  // namespace
}  // namespace strata::mcap

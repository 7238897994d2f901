// The MCAP writer's file structure, read back by a minimal reader of the spec's records
// (https://mcap.dev/spec): magic, the footer's and summary offsets' pointers, the chunk indexes', the
// message indexes', and the three CRCs. tests/interop/ reads whole files with the spec's own reader.
#include "drivers/mcap/mcap_writer.hpp"

#include <gtest/gtest.h>
#include <zstd.h>

#include <boost/crc.hpp>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace strata::mcap {
namespace {

template <typename T>
T read(const std::string& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

std::uint32_t crc32(std::string_view bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

struct Record {
  std::uint8_t opcode = 0;
  std::size_t offset = 0;  ///< of the opcode
  std::string content;
};

/// The record at `offset`.
Record record_at(const std::string& bytes, std::size_t offset) {
  const auto length = read<std::uint64_t>(bytes, offset + 1);
  return {static_cast<std::uint8_t>(bytes[offset]), offset, bytes.substr(offset + 9, length)};
}

/// Every record from `offset` to `end`.
std::vector<Record> records(const std::string& bytes, std::size_t offset, std::size_t end) {
  std::vector<Record> found;
  while (offset < end) {
    found.push_back(record_at(bytes, offset));
    offset += 9 + found.back().content.size();
  }
  return found;
}

const std::string kMagic("\x89MCAP0\r\n", 8);

std::string three_channel_file(Compression compression, std::size_t chunk_size) {
  McapWriter writer({.compression = compression, .chunk_size = chunk_size});
  const std::uint16_t schema = writer.add_schema("pkg/msg/A", "ros2msg", "int32 a\n");
  const std::uint16_t a = writer.add_channel(schema, "/a", "cdr", {{"k", "v"}});
  const std::uint16_t b = writer.add_channel(schema, "/b", "cdr");
  std::string file = writer.take_output();  // what a recorder would have flushed by now
  for (std::uint8_t i = 0; i < 10; ++i) {
    const std::vector<std::uint8_t> data(100, i);
    writer.add_message(i % 3 == 0 ? b : a, 1000 + i, 1000 + i, data);
  }
  writer.finish();
  return file + writer.take_output();
}

TEST(McapWriter, WritesMagicHeaderDataEndSummaryAndFooterThatPointAtEachOther) {
  for (const Compression compression : {Compression::kNone, Compression::kZstd}) {
    const std::string file = three_channel_file(compression, 350);  // 3 messages of 133 bytes a chunk
    ASSERT_EQ(file.substr(0, 8), kMagic);
    ASSERT_EQ(file.substr(file.size() - 8), kMagic);
    const Record header = record_at(file, 8);
    EXPECT_EQ(header.opcode, 0x01);
    EXPECT_EQ(header.content.substr(4, 4), "ros2");

    const Record footer = record_at(file, file.size() - 8 - 29);
    ASSERT_EQ(footer.opcode, 0x02);
    const auto summary_start = read<std::uint64_t>(footer.content, 0);
    const auto summary_offset_start = read<std::uint64_t>(footer.content, 8);
    // The summary's CRC: the summary, its offsets and the footer up to the CRC.
    EXPECT_EQ(
        read<std::uint32_t>(footer.content, 16),
        crc32(std::string_view(file).substr(summary_start, footer.offset + 1 + 8 + 16 - summary_start)));
    // Data End just before the summary, with the CRC of everything before it.
    const Record data_end = record_at(file, summary_start - 13);
    ASSERT_EQ(data_end.opcode, 0x0F);
    EXPECT_EQ(read<std::uint32_t>(data_end.content, 0),
              crc32(std::string_view(file).substr(0, data_end.offset)));

    // The summary grouped by opcode, and one Summary Offset per group pointing at it.
    std::map<std::uint8_t, std::vector<Record>> groups;
    for (Record& record : records(file, summary_start, summary_offset_start))
      groups[record.opcode].push_back(std::move(record));
    EXPECT_EQ(groups[0x03].size(), 1U);  // schema
    EXPECT_EQ(groups[0x04].size(), 2U);  // channels
    EXPECT_EQ(groups[0x08].size(), 4U);  // chunk indexes: 3 + 3 + 3 + 1 messages
    ASSERT_EQ(groups[0x0B].size(), 1U);  // statistics
    const std::string& statistics = groups[0x0B][0].content;
    EXPECT_EQ(read<std::uint64_t>(statistics, 0), 10U);
    EXPECT_EQ(read<std::uint32_t>(statistics, 22), 4U);  // chunks
    EXPECT_EQ(read<std::uint64_t>(statistics, 26), 1000U);
    EXPECT_EQ(read<std::uint64_t>(statistics, 34), 1009U);
    for (const Record& offset : records(file, summary_offset_start, footer.offset)) {
      ASSERT_EQ(offset.opcode, 0x0E);
      const auto group = static_cast<std::uint8_t>(offset.content[0]);
      EXPECT_EQ(read<std::uint64_t>(offset.content, 1), groups.at(group).front().offset);
      EXPECT_EQ(read<std::uint64_t>(offset.content, 9), groups.at(group).back().offset + 9 +
                                                            groups.at(group).back().content.size() -
                                                            groups.at(group).front().offset);
    }

    // Each chunk index points at its chunk and message indexes; each message index at its messages.
    std::size_t messages = 0;
    for (const Record& index : groups[0x08]) {
      const auto chunk_offset = read<std::uint64_t>(index.content, 16);
      const Record chunk = record_at(file, chunk_offset);
      ASSERT_EQ(chunk.opcode, 0x06);
      EXPECT_EQ(read<std::uint64_t>(index.content, 24), 9 + chunk.content.size());
      const auto uncompressed_size = read<std::uint64_t>(chunk.content, 16);
      const auto compression_length = read<std::uint32_t>(chunk.content, 28);
      const std::string stored = chunk.content.substr(32 + compression_length + 8);
      std::string records_bytes = stored;
      if (compression == Compression::kZstd) {
        EXPECT_EQ(chunk.content.substr(32, compression_length), "zstd");
        records_bytes.assign(uncompressed_size, '\0');
        ASSERT_EQ(ZSTD_decompress(records_bytes.data(), records_bytes.size(), stored.data(), stored.size()),
                  uncompressed_size);
      } else {
        EXPECT_EQ(compression_length, 0U);
      }
      EXPECT_EQ(records_bytes.size(), uncompressed_size);
      EXPECT_EQ(read<std::uint32_t>(chunk.content, 24), crc32(records_bytes));
      const auto map_length = read<std::uint32_t>(index.content, 32);
      for (std::size_t entry = 0; entry < map_length; entry += 10) {
        const auto channel = read<std::uint16_t>(index.content, 36 + entry);
        const Record message_index = record_at(file, read<std::uint64_t>(index.content, 36 + entry + 2));
        ASSERT_EQ(message_index.opcode, 0x07);
        EXPECT_EQ(read<std::uint16_t>(message_index.content, 0), channel);
        const auto pairs = read<std::uint32_t>(message_index.content, 2);
        for (std::size_t pair = 0; pair < pairs; pair += 16) {
          const auto log_time = read<std::uint64_t>(message_index.content, 6 + pair);
          const Record message =
              record_at(records_bytes, read<std::uint64_t>(message_index.content, 14 + pair));
          ASSERT_EQ(message.opcode, 0x05);
          EXPECT_EQ(read<std::uint16_t>(message.content, 0), channel);
          EXPECT_EQ(read<std::uint64_t>(message.content, 6), log_time);
          EXPECT_EQ(static_cast<std::uint8_t>(message.content.back()), log_time - 1000);
          ++messages;
        }
      }
    }
    EXPECT_EQ(messages, 10U);
  }
}

TEST(McapWriter, NumbersEachChannelsMessagesFromZero) {
  McapWriter writer({.compression = Compression::kNone});
  const std::uint16_t a = writer.add_channel(0, "/a", "json");
  const std::uint16_t b = writer.add_channel(0, "/b", "json");
  const std::vector<std::uint8_t> data{'{', '}'};
  writer.add_message(a, 1, 1, data);
  writer.add_message(b, 2, 2, data);
  writer.add_message(a, 3, 3, data);
  writer.close_chunk();
  const std::string file = writer.take_output();
  std::vector<Record> chunks;
  for (Record& record : records(file, 8, file.size()))
    if (record.opcode == 0x06)
      chunks.push_back(std::move(record));
  ASSERT_EQ(chunks.size(), 1U);
  const Record& chunk = chunks[0];
  std::vector<std::uint32_t> sequences;
  const std::string records_bytes = chunk.content.substr(32 + 8);
  for (const Record& message : records(records_bytes, 0, records_bytes.size()))
    sequences.push_back(read<std::uint32_t>(message.content, 2));
  EXPECT_EQ(sequences, (std::vector<std::uint32_t>{0, 0, 1}));
}

TEST(McapWriter, RefusesMessagesOnUnknownChannels) {
  McapWriter writer;
  EXPECT_THROW(writer.add_message(0, 1, 1, {}), std::invalid_argument);
  EXPECT_THROW((void)writer.add_channel(3, "/a", "cdr"), std::invalid_argument);
}

}  // namespace
}  // namespace strata::mcap

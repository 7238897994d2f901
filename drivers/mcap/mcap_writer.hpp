#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "drivers/mcap/mcap_format.hpp"
#include "drivers/mcap/record_buffer.hpp"

namespace strata::mcap {

enum class Compression { kNone, kZstd };

struct McapWriterOptions {
  Compression compression = Compression::kZstd;
  std::size_t chunk_size = 1 << 20;  ///< uncompressed record bytes at which a chunk is closed
  std::string profile = "ros2";      ///< the Header's profile: what the channels' encodings follow
  std::string library = "strata";
};

/// Writes an MCAP file (https://mcap.dev/spec) into memory, for its owner to put where it belongs: a whole
/// file written atomically, or a recording appended to as it goes. Layout: magic, Header; Schema and
/// Channel records as they are added; Messages in Chunks (zstd or uncompressed, each with the CRC32 of
/// its records), each Chunk followed by a Message Index per channel; then Data End (the data section's
/// CRC32), the Summary (Schemas, Channels, Chunk Indexes, Statistics), a Summary Offset per group, Footer
/// (the summary's CRC32), magic. So a viewer seeks by the index, and a file cut short (a killed
/// recorder) still reads up to its last whole chunk: take_output() after close_chunk() hands over bytes
/// that never change again.
class McapWriter {
 public:
  /// Starts the file: magic and Header.
  explicit McapWriter(McapWriterOptions options = {});

  /// A Schema record; returns its id (1, 2, ...).
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  /// A Channel record on `schema_id` (0: none); returns its id (0, 1, ...).
  std::uint16_t add_channel(std::uint16_t schema_id, std::string_view topic,
                            std::string_view message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  /// A Message on `channel_id` into the open chunk, with the channel's next sequence number; the chunk
  /// closes when it reaches options.chunk_size. Throws std::invalid_argument for an unknown channel.
  void add_message(std::uint16_t channel_id, std::uint64_t log_time, std::uint64_t publish_time,
                   std::span<const std::uint8_t> data);
  /// Writes the open chunk (if it holds anything) and its message indexes.
  void close_chunk();
  /// Closes the chunk and writes Data End, the summary, the footer and the closing magic. Nothing can be
  /// added after.
  void finish();

  /// The bytes written since the last call (all of them, the first time).
  [[nodiscard]] std::string take_output();
  /// Bytes written so far, taken or not: where the next record starts.
  [[nodiscard]] std::uint64_t position() const { return taken_ + output_.size(); }

 private:
  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length = 0, compressed_size = 0, uncompressed_size = 0;
  };
  struct Channel {
    std::string record;  ///< its Channel record's content, for the summary
    std::uint32_t next_sequence = 0;
    std::uint64_t messages = 0;
  };

  /// Appends a record to the data section (whose CRC it updates) or, after Data End, the summary.
  void write_record(std::uint8_t opcode, std::string_view content);
  /// The summary's records of one opcode, returning its Summary Offset group (start, length).
  std::pair<std::uint64_t, std::uint64_t> write_group(std::uint8_t opcode,
                                                      const std::vector<std::string>& records);

  McapWriterOptions options_;
  std::string output_;       ///< written, not yet taken
  std::uint64_t taken_ = 0;  ///< bytes taken before output_
  Crc32 data_crc_;           ///< of everything before Data End
  bool finished_ = false;

  std::vector<std::string> schemas_;  ///< Schema record contents, id - 1
  std::vector<Channel> channels_;     ///< by id

  RecordBuffer chunk_records_;  ///< the open chunk's records, uncompressed
  std::uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>>
      chunk_index_;  ///< log time, offset
  std::vector<ChunkIndex> chunks_;

  std::uint64_t message_count_ = 0, start_time_ = 0, end_time_ = 0;
};

}  // namespace strata::mcap

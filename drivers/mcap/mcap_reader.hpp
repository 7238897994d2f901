#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <istream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace strata::mcap {

/// A file that is not a whole, intact MCAP file: says what is wrong and at which byte.
class McapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct McapChannel {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;
  std::string schema_name;  ///< the type ("sensor_msgs/msg/PointCloud2"), empty without a schema
};

/// Where one message is: its data is read by McapReader::message_data.
struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;
  std::size_t chunk = 0;     ///< index into the reader's chunks (its file offset)
  std::uint64_t offset = 0;  ///< of the data in the chunk's uncompressed records
  std::uint64_t size = 0;
};

/// Reads an MCAP file (https://mcap.dev/spec) as McapWriter writes it, and checks all of it before any
/// of it is used: the magic at both ends, every record's length against the file, the Header first,
/// every Chunk's compression ("zstd" or none), its uncompressed size and CRC32, the records inside it,
/// each message's channel, the data section's CRC in Data End, the footer and the summary's CRC. A file
/// cut short (a recorder that was killed) or damaged anywhere is refused with an McapError. Messages are
/// listed in file order; their bytes are read (their chunk decompressed again) when asked for, so a long
/// recording is never held in memory.
class McapReader {
 public:
  /// Largest chunk (uncompressed) or record taken: a damaged length must not allocate gigabytes.
  static constexpr std::uint64_t kMaxRecordSize = std::uint64_t{1} << 28;  // 256 MiB: a chunk is ~1 MiB

  /// Throws McapError naming the file, the byte offset and what is wrong.
  explicit McapReader(const std::filesystem::path& file);
  /// The same over any seekable stream (`name` for the errors): a file in memory, the fuzz target's.
  McapReader(std::unique_ptr<std::istream> in, std::string name);

  [[nodiscard]] const std::vector<McapChannel>& channels() const { return channels_; }
  [[nodiscard]] const std::vector<McapMessage>& messages() const { return messages_; }
  /// The channel of that topic, or nullptr.
  [[nodiscard]] const McapChannel* channel(std::string_view topic) const;
  /// The message's bytes (its chunk is read and decompressed again unless it was the last one read).
  /// Throws McapError when the file changed since it was checked.
  [[nodiscard]] std::string message_data(const McapMessage& message);

 private:
  struct Chunk {
    std::uint64_t offset = 0;  ///< of its record in the file
  };
  void read_file();
  /// The uncompressed records of the chunk whose record content is `content` (at `offset`), checked.
  std::string chunk_records(const std::string& content, std::uint64_t offset) const;
  void read_chunk(const std::string& content, std::uint64_t offset);
  [[nodiscard]] std::string read_record_content(std::uint64_t offset);

  std::string name_;
  std::unique_ptr<std::istream> in_;
  std::uint64_t size_ = 0;
  std::vector<McapChannel> channels_;
  std::vector<std::uint16_t> schema_ids_;  ///< the Schema records seen
  std::vector<std::string> schema_names_;  ///< by the same index
  std::vector<Chunk> chunks_;
  std::vector<McapMessage> messages_;
  std::size_t cached_chunk_ = std::numeric_limits<std::size_t>::max();
  std::string cached_records_;
};

}  // namespace strata::mcap

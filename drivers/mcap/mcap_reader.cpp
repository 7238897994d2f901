#include "drivers/mcap/mcap_reader.hpp"

#include <spdlog/fmt/fmt.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>

#include "drivers/mcap/mcap_format.hpp"

namespace strata::mcap {
namespace {

constexpr std::size_t kRecordPrefix = 9;  // opcode, uint64 length

/// Reads the fields of one record's content, refusing to read past its end.
class FieldReader {
 public:
  FieldReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <typename T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  std::string_view get_string() { return take(get<std::uint32_t>()); }
  std::string_view take(std::uint64_t size) {
    if (size > bytes_.size() - position_)
      throw McapError(fmt::format("{} is shorter than its fields ({} bytes wanted at {} of {})", what_, size,
                                  position_, bytes_.size()));
    const std::string_view taken = bytes_.substr(position_, size);
    position_ += size;
    return taken;
  }
  [[nodiscard]] std::uint64_t position() const { return position_; }
  [[nodiscard]] bool done() const { return position_ == bytes_.size(); }

 private:
  std::string_view bytes_;
  std::string what_;
  std::uint64_t position_ = 0;
};

/// "a chunk (opcode 0x06)": how errors name a record.
std::string record_name(std::uint8_t opcode) {
  static const char* const kNames[] = {"a record",      "the Header",          "the Footer",
                                       "a Schema",      "a Channel",           "a Message",
                                       "a Chunk",       "a Message Index",     "a Chunk Index",
                                       "an Attachment", "an Attachment Index", "the Statistics",
                                       "a Metadata",    "a Metadata Index",    "a Summary Offset",
                                       "the Data End"};
  return fmt::format("{} (opcode 0x{:02x})", opcode < std::size(kNames) ? kNames[opcode] : "a record",
                     static_cast<unsigned>(opcode));
}

std::string record_prefix(std::uint8_t opcode, std::uint64_t length) {
  std::string prefix(kRecordPrefix, '\0');
  prefix[0] = static_cast<char>(opcode);
  std::memcpy(prefix.data() + 1, &length, sizeof(length));
  return prefix;
}

}  // namespace

McapReader::McapReader(const std::filesystem::path& file)
    : McapReader(std::make_unique<std::ifstream>(file, std::ios::binary), file.string()) {}

McapReader::McapReader(std::unique_ptr<std::istream> in, std::string name)
    : name_(std::move(name)), in_(std::move(in)) {
  if (!*in_)
    throw McapError(name_ + ": cannot open");
  try {
    read_file();
  } catch (const McapError& e) {
    throw McapError(name_ + ": " + e.what());
  }
}

const McapChannel* McapReader::channel(std::string_view topic) const {
  const auto found = std::ranges::find(channels_, topic, &McapChannel::topic);
  return found == channels_.end() ? nullptr : &*found;
}

std::string McapReader::read_record_content(std::uint64_t offset) {
  if (offset + kRecordPrefix > size_)
    throw McapError(
        fmt::format("cut short: the file ends at byte {} inside the record starting at {}", size_, offset));
  std::string prefix(kRecordPrefix, '\0');
  in_->clear();
  in_->seekg(static_cast<std::streamoff>(offset));
  in_->read(prefix.data(), kRecordPrefix);
  std::uint64_t length = 0;
  std::memcpy(&length, prefix.data() + 1, sizeof(length));
  if (length > size_ - offset - kRecordPrefix) {
    throw McapError(fmt::format("cut short: {} at byte {} holds {} bytes, the file ends {} bytes after it",
                                record_name(static_cast<std::uint8_t>(prefix[0])), offset, length,
                                size_ - offset - kRecordPrefix));
  }
  if (length > kMaxRecordSize)
    throw McapError(
        fmt::format("the record at byte {} claims {} bytes, more than this reader takes", offset, length));
  std::string content(length, '\0');
  in_->read(content.data(), static_cast<std::streamsize>(length));
  if (!*in_)
    throw McapError(fmt::format("cannot read the record at byte {}", offset));
  return content;
}

void McapReader::read_file() {
  in_->seekg(0, std::ios::end);
  const std::streamoff size = in_->tellg();
  if (size < 0)
    throw McapError("cannot tell the file's size");
  size_ = static_cast<std::uint64_t>(size);
  in_->seekg(0);
  std::string magic(kMagic.size(), '\0');
  in_->read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (!*in_ || magic != kMagic)
    throw McapError("not an MCAP file (it does not start with the MCAP magic)");
  Crc32 data_crc;  // of everything before Data End
  data_crc.update(magic);
  std::uint64_t offset = kMagic.size();
  bool header_seen = false, data_end_seen = false;
  std::uint64_t summary_crc_start = 0;
  while (true) {
    if (offset == size_)
      throw McapError(
          fmt::format("cut short: no footer after byte {} (the recording was not finished: a "
                      "killed recorder leaves such a file; other MCAP readers read its whole "
                      "chunks)",
                      offset));
    const std::string content = read_record_content(offset);
    in_->seekg(static_cast<std::streamoff>(offset));
    char opcode_byte = 0;
    in_->get(opcode_byte);
    const auto opcode = static_cast<std::uint8_t>(opcode_byte);
    const std::string prefix = record_prefix(opcode, content.size());
    const std::string what = fmt::format("{} at byte {}", record_name(opcode), offset);
    if (!header_seen && opcode != kHeader)
      throw McapError(what + " comes before the Header");
    FieldReader fields(content, what);
    switch (opcode) {
      case kHeader:
        if (header_seen)
          throw McapError(what + " is a second Header");
        header_seen = true;
        break;
      case kSchema: {
        const auto id = fields.get<std::uint16_t>();
        const std::string name(fields.get_string());
        if (!data_end_seen && std::ranges::find(schema_ids_, id) == schema_ids_.end()) {
          schema_ids_.push_back(id);
          schema_names_.push_back(name);
        }
        break;
      }
      case kChannel: {
        McapChannel channel;
        channel.id = fields.get<std::uint16_t>();
        const auto schema_id = fields.get<std::uint16_t>();
        channel.topic = fields.get_string();
        channel.message_encoding = fields.get_string();
        const auto schema = std::ranges::find(schema_ids_, schema_id);
        if (schema_id != 0 && schema == schema_ids_.end())
          throw McapError(what + ": channel " + channel.topic + " names a schema not defined before it");
        if (schema_id != 0)
          channel.schema_name = schema_names_[static_cast<std::size_t>(schema - schema_ids_.begin())];
        if (!data_end_seen && std::ranges::find(channels_, channel.id, &McapChannel::id) == channels_.end())
          channels_.push_back(std::move(channel));
        break;
      }
      case kMessage:
        throw McapError(what +
                        ": a message outside a chunk (this reader reads chunked files, as Strata "
                        "writes them)");
      case kChunk:
        if (data_end_seen)
          throw McapError(what + ": a chunk after Data End");
        read_chunk(content, offset);
        break;
      case kDataEnd: {
        const auto crc = fields.get<std::uint32_t>();
        if (crc != 0 && crc != data_crc.value())
          throw McapError(
              fmt::format("{}: the data section's CRC32 is {:08x}, Data End says {:08x} (the "
                          "file is damaged)",
                          what, data_crc.value(), crc));
        data_end_seen = true;
        summary_crc_start = offset + kRecordPrefix + content.size();
        break;
      }
      case kFooter: {
        const auto summary_start = fields.get<std::uint64_t>();
        fields.get<std::uint64_t>();  // summary offset start
        const auto crc = fields.get<std::uint32_t>();
        if (!data_end_seen)
          throw McapError(what + ": a footer without Data End");
        const std::uint64_t crc_from = summary_start != 0 ? summary_start : offset;
        if (crc != 0) {
          if (crc_from < summary_crc_start || crc_from > offset)
            throw McapError(what + ": the footer's summary start lies outside the summary");
          std::string covered(offset - crc_from, '\0');
          in_->seekg(static_cast<std::streamoff>(crc_from));
          in_->read(covered.data(), static_cast<std::streamsize>(covered.size()));
          covered += prefix + content.substr(0, content.size() - sizeof(std::uint32_t));
          if (crc32_of(covered) != crc)
            throw McapError(what + ": the summary's CRC32 does not match the footer's (the file is damaged)");
        }
        const std::uint64_t end = offset + kRecordPrefix + content.size();
        std::string closing(kMagic.size(), '\0');
        in_->seekg(static_cast<std::streamoff>(end));
        in_->read(closing.data(), static_cast<std::streamsize>(closing.size()));
        if (!*in_ || closing != kMagic || end + kMagic.size() != size_)
          throw McapError(
              fmt::format("the footer at byte {} is not followed by the closing magic and the "
                          "file's end (cut short or damaged)",
                          offset));
        return;
      }
      default:
        break;  // message indexes, the summary's indexes and statistics, metadata, attachments: not needed
    }
    if (!data_end_seen) {
      data_crc.update(prefix);
      data_crc.update(content);
    }
    offset += kRecordPrefix + content.size();
  }
}

std::string McapReader::chunk_records(const std::string& content, std::uint64_t offset) const {
  FieldReader fields(content, fmt::format("the chunk at byte {}", offset));
  fields.get<std::uint64_t>();  // start time
  fields.get<std::uint64_t>();  // end time
  const auto uncompressed_size = fields.get<std::uint64_t>();
  const auto uncompressed_crc = fields.get<std::uint32_t>();
  const std::string compression(fields.get_string());
  const auto stored_size = fields.get<std::uint64_t>();
  const std::string_view stored = fields.take(stored_size);
  if (uncompressed_size > kMaxRecordSize)
    throw McapError(
        fmt::format("the chunk at byte {} claims {} bytes uncompressed", offset, uncompressed_size));
  std::string records;
  if (compression.empty()) {
    records = stored;
  } else if (compression == "zstd") {
    // One frame that says its size, as ZSTD_compress writes it: a damaged claim is refused before it is
    // allocated.
    const std::size_t frame_bytes = ZSTD_findFrameCompressedSize(stored.data(), stored.size());
    const unsigned long long frame_size = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (ZSTD_isError(frame_bytes) != 0 || frame_bytes != stored.size() || frame_size != uncompressed_size)
      throw McapError(fmt::format("the chunk at byte {} is not one zstd frame of its {} bytes that says so",
                                  offset, uncompressed_size));
    records.resize(uncompressed_size);
    const std::size_t size = ZSTD_decompress(records.data(), records.size(), stored.data(), stored.size());
    if (ZSTD_isError(size) != 0)
      throw McapError(
          fmt::format("the chunk at byte {} does not decompress: {}", offset, ZSTD_getErrorName(size)));
    records.resize(size);
  } else {
    throw McapError(
        fmt::format("the chunk at byte {} is compressed with '{}' (this reader takes zstd or none)", offset,
                    compression));
  }
  if (records.size() != uncompressed_size)
    throw McapError(fmt::format("the chunk at byte {} holds {} bytes, its record says {}", offset,
                                records.size(), uncompressed_size));
  if (uncompressed_crc != 0 && crc32_of(records) != uncompressed_crc)
    throw McapError(
        fmt::format("the chunk at byte {}: its CRC32 does not match (the file is damaged)", offset));
  return records;
}

void McapReader::read_chunk(const std::string& content, std::uint64_t offset) {
  const std::string records = chunk_records(content, offset);
  const std::size_t chunk = chunks_.size();
  chunks_.push_back({offset});
  FieldReader reader(records, fmt::format("the chunk at byte {}", offset));
  while (!reader.done()) {
    const auto opcode = reader.get<std::uint8_t>();
    const auto length = reader.get<std::uint64_t>();
    const std::uint64_t start = reader.position();
    FieldReader fields(reader.take(length), fmt::format("a record in the chunk at byte {}", offset));
    if (opcode == kMessage) {
      McapMessage message;
      message.channel_id = fields.get<std::uint16_t>();
      message.sequence = fields.get<std::uint32_t>();
      message.log_time = fields.get<std::uint64_t>();
      fields.get<std::uint64_t>();  // publish time
      message.chunk = chunk;
      message.offset = start + fields.position();
      message.size = length - fields.position();
      if (std::ranges::find(channels_, message.channel_id, &McapChannel::id) == channels_.end())
        throw McapError(
            fmt::format("a message in the chunk at byte {} is on channel {}, not defined before it", offset,
                        message.channel_id));
      messages_.push_back(message);
    } else if (opcode == kSchema || opcode == kChannel) {
      throw McapError(
          fmt::format("a schema or channel inside the chunk at byte {} (Strata writes them "
                      "before the chunks)",
                      offset));
    }
  }
}

std::string McapReader::message_data(const McapMessage& message) {
  if (message.chunk >= chunks_.size())
    throw McapError(name_ + ": no such chunk");
  if (cached_chunk_ != message.chunk) {
    const std::uint64_t offset = chunks_[message.chunk].offset;
    try {
      cached_records_ = chunk_records(read_record_content(offset), offset);
    } catch (const McapError& e) {
      throw McapError(name_ + ": " + e.what());
    }
    cached_chunk_ = message.chunk;
  }
  if (message.offset + message.size > cached_records_.size())
    throw McapError(name_ + ": a message beyond its chunk (the file changed)");
  return cached_records_.substr(message.offset, message.size);
}

}  // namespace strata::mcap

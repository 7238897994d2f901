#include "drivers/mcap/mcap_writer.hpp"

#include <zstd.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "drivers/mcap/mcap_format.hpp"

namespace strata::mcap {
namespace {

std::string zstd_compressed(const std::string& records) {
  std::string compressed(ZSTD_compressBound(records.size()), '\0');
  const std::size_t size = ZSTD_compress(compressed.data(), compressed.size(), records.data(), records.size(),
                                         ZSTD_CLEVEL_DEFAULT);
  if (ZSTD_isError(size) != 0)
    throw std::runtime_error(std::string("zstd compression failed: ") + ZSTD_getErrorName(size));
  compressed.resize(size);
  return compressed;
}

/// Map<uint16, uint64> or Array<Tuple<uint64, uint64>>: the uint32 byte length, then the pairs.
template <typename First, typename Range>
void put_pairs(RecordBuffer& out, const Range& pairs) {
  out.put(static_cast<std::uint32_t>(std::size(pairs) * (sizeof(First) + sizeof(std::uint64_t))));
  for (const auto& [first, second] : pairs) {
    out.put(static_cast<First>(first));
    out.put(static_cast<std::uint64_t>(second));
  }
}

}  // namespace

McapWriter::McapWriter(McapWriterOptions options) : options_(std::move(options)) {
  output_.append(kMagic);
  data_crc_.update(kMagic);
  RecordBuffer header;
  header.put_string(options_.profile);
  header.put_string(options_.library);
  write_record(kHeader, header.bytes());
}

void McapWriter::write_record(std::uint8_t opcode, std::string_view content) {
  RecordBuffer record;
  record.put_record(opcode, content);
  if (!finished_)
    data_crc_.update(record.bytes());
  output_.append(record.bytes());
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::string_view data) {
  if (finished_ || schemas_.size() >= std::numeric_limits<std::uint16_t>::max())
    throw std::logic_error("MCAP schema after finish() or beyond 65535 schemas");
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  RecordBuffer schema;
  schema.put(id);
  schema.put_string(name);
  schema.put_string(encoding);
  schema.put_string(data);  // uint32-length-prefixed bytes: a String's layout
  // Before the open chunk's bytes, which are written when it closes: a channel's schema is always earlier
  // in the file than the channel's messages.
  write_record(kSchema, schema.bytes());
  schemas_.push_back(schema.take());
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, std::string_view topic,
                                      std::string_view message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  if (finished_ || channels_.size() > std::numeric_limits<std::uint16_t>::max())
    throw std::logic_error("MCAP channel after finish() or beyond 65536 channels");
  if (schema_id > schemas_.size())
    throw std::invalid_argument("MCAP channel " + std::string(topic) + " names an unknown schema");
  const auto id = static_cast<std::uint16_t>(channels_.size());
  RecordBuffer channel;
  channel.put(id);
  channel.put(schema_id);
  channel.put_string(topic);
  channel.put_string(message_encoding);
  RecordBuffer entries;
  for (const auto& [key, value] : metadata) {
    entries.put_string(key);
    entries.put_string(value);
  }
  channel.put_string(entries.bytes());  // Map<string, string>: uint32 byte length, then the entries
  write_record(kChannel, channel.bytes());
  channels_.push_back({channel.take()});
  return id;
}

void McapWriter::add_message(std::uint16_t channel_id, std::uint64_t log_time, std::uint64_t publish_time,
                             std::span<const std::uint8_t> data) {
  if (finished_)
    throw std::logic_error("MCAP message after finish()");
  if (channel_id >= channels_.size())
    throw std::invalid_argument("MCAP message on unknown channel " + std::to_string(channel_id));
  Channel& channel = channels_[channel_id];
  chunk_index_[channel_id].emplace_back(log_time, chunk_records_.size());
  RecordBuffer message;
  message.put(channel_id);
  message.put(channel.next_sequence++);
  message.put(log_time);
  message.put(publish_time);
  message.put_bytes({reinterpret_cast<const char*>(data.data()), data.size()});
  chunk_records_.put_record(kMessage, message.bytes());
  ++channel.messages;

  const bool first_in_chunk = chunk_index_.size() == 1 && chunk_index_.begin()->second.size() == 1;
  chunk_start_time_ = first_in_chunk ? log_time : std::min(chunk_start_time_, log_time);
  chunk_end_time_ = first_in_chunk ? log_time : std::max(chunk_end_time_, log_time);
  start_time_ = message_count_ == 0 ? log_time : std::min(start_time_, log_time);
  end_time_ = message_count_ == 0 ? log_time : std::max(end_time_, log_time);
  ++message_count_;
  if (chunk_records_.size() >= options_.chunk_size)
    close_chunk();
}

void McapWriter::close_chunk() {
  if (chunk_records_.size() == 0)
    return;
  const std::string& records = chunk_records_.bytes();
  const bool zstd = options_.compression == Compression::kZstd;
  const std::string compressed = zstd ? zstd_compressed(records) : std::string();
  const std::string_view stored = zstd ? std::string_view(compressed) : std::string_view(records);

  ChunkIndex index;
  index.start_time = chunk_start_time_;
  index.end_time = chunk_end_time_;
  index.offset = position();
  index.compressed_size = stored.size();
  index.uncompressed_size = records.size();
  RecordBuffer chunk;
  chunk.put(chunk_start_time_);
  chunk.put(chunk_end_time_);
  chunk.put(static_cast<std::uint64_t>(records.size()));
  chunk.put(crc32_of(records));
  chunk.put_string(zstd ? "zstd" : "");
  chunk.put(static_cast<std::uint64_t>(stored.size()));
  chunk.put_bytes(stored);
  write_record(kChunk, chunk.bytes());
  index.length = position() - index.offset;

  const std::uint64_t indexes_start = position();
  for (const auto& [channel_id, entries] : chunk_index_) {
    index.message_index_offsets[channel_id] = position();
    RecordBuffer message_index;
    message_index.put(channel_id);
    put_pairs<std::uint64_t>(message_index, entries);
    write_record(kMessageIndex, message_index.bytes());
  }
  index.message_index_length = position() - indexes_start;
  chunks_.push_back(std::move(index));
  chunk_records_.clear();
  chunk_index_.clear();
}

std::pair<std::uint64_t, std::uint64_t> McapWriter::write_group(std::uint8_t opcode,
                                                                const std::vector<std::string>& records) {
  const std::uint64_t start = position();
  for (const std::string& record : records)
    write_record(opcode, record);
  return {start, position() - start};
}

void McapWriter::finish() {
  if (finished_)
    return;
  close_chunk();
  RecordBuffer data_end;
  data_end.put(data_crc_.value());
  finished_ = true;  // from here on the records are the summary's: no longer in the data section's CRC
  write_record(kDataEnd, data_end.bytes());

  const std::uint64_t summary_start = position();
  std::vector<std::string> channels;
  for (const Channel& channel : channels_)
    channels.push_back(channel.record);
  std::vector<std::string> chunk_indexes;
  for (const ChunkIndex& chunk : chunks_) {
    RecordBuffer index;
    index.put(chunk.start_time);
    index.put(chunk.end_time);
    index.put(chunk.offset);
    index.put(chunk.length);
    put_pairs<std::uint16_t>(index, chunk.message_index_offsets);
    index.put(chunk.message_index_length);
    index.put_string(options_.compression == Compression::kZstd ? "zstd" : "");
    index.put(chunk.compressed_size);
    index.put(chunk.uncompressed_size);
    chunk_indexes.push_back(index.take());
  }
  RecordBuffer statistics;
  statistics.put(message_count_);
  statistics.put(static_cast<std::uint16_t>(schemas_.size()));
  statistics.put(static_cast<std::uint32_t>(channels_.size()));
  statistics.put(std::uint32_t{0});  // attachments
  statistics.put(std::uint32_t{0});  // metadata
  statistics.put(static_cast<std::uint32_t>(chunks_.size()));
  statistics.put(start_time_);
  statistics.put(end_time_);
  std::map<std::uint16_t, std::uint64_t> counts;
  for (std::size_t id = 0; id < channels_.size(); ++id)
    counts[static_cast<std::uint16_t>(id)] = channels_[id].messages;
  put_pairs<std::uint16_t>(statistics, counts);

  const std::pair<std::uint8_t, std::pair<std::uint64_t, std::uint64_t>> groups[] = {
      {kSchema, write_group(kSchema, schemas_)},
      {kChannel, write_group(kChannel, channels)},
      {kChunkIndex, write_group(kChunkIndex, chunk_indexes)},
      {kStatistics, write_group(kStatistics, {statistics.take()})},
  };
  const std::uint64_t summary_offset_start = position();
  for (const auto& [opcode, group] : groups) {
    if (group.second == 0)
      continue;
    RecordBuffer offset;
    offset.put(opcode);
    offset.put(group.first);
    offset.put(group.second);
    write_record(kSummaryOffset, offset.bytes());
  }
  // The footer's CRC covers the summary, the summary offsets and the footer up to the CRC itself.
  RecordBuffer footer;
  footer.put(summary_start);
  footer.put(summary_offset_start);
  RecordBuffer footer_prefix;
  footer_prefix.put_record(kFooter, footer.bytes() + std::string(4, '\0'));
  Crc32 summary_crc;
  const std::size_t summary_in_output = output_.size() - (position() - summary_start);
  summary_crc.update(std::string_view(output_).substr(summary_in_output));
  summary_crc.update(std::string_view(footer_prefix.bytes()).substr(0, footer_prefix.size() - 4));
  footer.put(summary_crc.value());
  write_record(kFooter, footer.bytes());
  output_.append(kMagic);
}

std::string McapWriter::take_output() {
  taken_ += output_.size();
  return std::exchange(output_, std::string());
}

}  // namespace strata::mcap

#pragma once

#include <boost/crc.hpp>
#include <cstdint>
#include <string_view>

namespace strata::mcap {

// The MCAP format's constants (https://mcap.dev/spec), shared by the writer and the reader.

inline constexpr std::string_view kMagic("\x89MCAP0\r\n", 8);

/// Record opcodes ("Records").
enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The CRC-32 every MCAP checksum is (the zlib one).
[[nodiscard]] inline std::uint32_t crc32(std::string_view bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

}  // namespace strata::mcap

#pragma once

#include <zlib.h>

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

/// The CRC-32 every MCAP checksum is, computed as it goes: zlib's, several times faster than a byte-wise
/// table (Boost.CRC's), which made the two CRCs most of a recording's CPU time (docs/benchmarks.md).
class Crc32 {
 public:
  void update(std::string_view bytes) {
    crc_ = ::crc32_z(crc_, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size());
  }
  [[nodiscard]] std::uint32_t value() const { return static_cast<std::uint32_t>(crc_); }

 private:
  uLong crc_ = 0;  // crc32_z(0, Z_NULL, 0)
};

[[nodiscard]] inline std::uint32_t crc32_of(std::string_view bytes) {
  Crc32 crc;
  crc.update(bytes);
  return crc.value();
}

}  // namespace strata::mcap

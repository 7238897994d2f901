#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "drivers/ros2/cdr_writer.hpp"

namespace strata::ros2 {

/// A CDR message that does not hold what its type says (cut short, a bad encapsulation header).
class CdrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads what CdrWriter writes (plain CDR, little-endian, aligned from the end of the 4-byte header),
/// refusing to read past the end.
class CdrReader {
 public:
  /// Throws CdrError unless `bytes` start with the CDR_LE encapsulation header.
  explicit CdrReader(std::span<const std::uint8_t> bytes);

  template <typename T>
  requires std::is_arithmetic_v<T> T read() {
    align(sizeof(T));
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  [[nodiscard]] std::string read_string();
  /// A sequence's element count; the caller reads the elements.
  [[nodiscard]] std::uint32_t read_sequence_size() { return read<std::uint32_t>(); }
  /// A uint8[] sequence: the count and the bytes.
  [[nodiscard]] std::span<const std::uint8_t> read_byte_sequence() { return take(read_sequence_size()); }

 private:
  void align(std::size_t size);
  std::span<const std::uint8_t> take(std::size_t size);

  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = kEncapsulationHeader;
};

}  // namespace strata::ros2

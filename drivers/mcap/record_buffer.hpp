#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

namespace strata::mcap {

static_assert(std::endian::native == std::endian::little, "MCAP's integers are little-endian, as the host's");

/// The bytes of MCAP records as the spec serializes their fields (https://mcap.dev/spec, "Serialization"):
/// little-endian integers; a String is its uint32 byte length and the bytes.
class RecordBuffer {
 public:
  template <typename T>
  void put(T value) {
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void put_string(std::string_view text) {
    put(static_cast<std::uint32_t>(text.size()));
    bytes_.append(text);
  }
  void put_bytes(std::string_view bytes) { bytes_.append(bytes); }
  /// A whole record: opcode, content length (uint64), content.
  void put_record(std::uint8_t opcode, std::string_view content) {
    put(opcode);
    put(static_cast<std::uint64_t>(content.size()));
    bytes_.append(content);
  }

  [[nodiscard]] const std::string& bytes() const { return bytes_; }
  [[nodiscard]] std::size_t size() const { return bytes_.size(); }
  [[nodiscard]] std::string take() { return std::move(bytes_); }
  void clear() { bytes_.clear(); }

 private:
  std::string bytes_;
};

}  // namespace strata::mcap

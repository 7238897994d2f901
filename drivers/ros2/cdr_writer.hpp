#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

namespace strata::ros2 {

/// CDR_LE: the 4 bytes every message starts with; alignment counts from their end.
inline constexpr std::size_t kEncapsulationHeader = 4;

/// Serializes a ROS 2 message as the DDS middleware puts it on the wire and rosbag2 stores it: plain CDR
/// (XCDR1), little-endian. The bytes start with the 4-byte encapsulation header 00 01 00 00 (CDR_LE);
/// every primitive is aligned to its own size (8 at most) counted from the end of that header. A string is
/// its byte count including a closing NUL (uint32), the bytes and the NUL; a sequence is its element count
/// (uint32) and the elements; a fixed-size array (float64[36]) is its elements alone.
class CdrWriter {
 public:
  CdrWriter();

  template <typename T>
  requires std::is_arithmetic_v<T>
  void write(T value) {
    align(sizeof(T));
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
    bytes_.insert(bytes_.end(), bytes, bytes + sizeof(T));  // little-endian: the host's order (x86, ARM)
  }
  void write_bool(bool value) { write(static_cast<std::uint8_t>(value ? 1 : 0)); }
  void write_string(std::string_view text);
  /// A sequence's element count; the caller writes the elements.
  void write_sequence_size(std::size_t count);
  /// A uint8[] or int8[] sequence: the count and the bytes.
  void write_byte_sequence(std::span<const std::uint8_t> data);
  /// A fixed-size array of float64 (a covariance): the elements only.
  void write_doubles(std::span<const double> values);

  [[nodiscard]] const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  [[nodiscard]] std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  /// Pads with zeros to a multiple of `size` after the encapsulation header.
  void align(std::size_t size);

  std::vector<std::uint8_t> bytes_;
};

}  // namespace strata::ros2

#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string_view>

namespace strata::io {

/// A scalar type as point-cloud files name it, with its size in bytes.
enum class ScalarKind { kInt, kUnsigned, kFloat };
struct ScalarType {
  ScalarKind kind = ScalarKind::kFloat;
  std::size_t size = 4;
};

/// Reads one scalar of `type` at `bytes` as double, byte-swapping when the file's endianness differs.
[[nodiscard]] inline double read_scalar(const unsigned char* bytes, ScalarType type, bool big_endian) {
  unsigned char buffer[8];
  std::memcpy(buffer, bytes, type.size);
  if (big_endian != (std::endian::native == std::endian::big)) {
    for (std::size_t i = 0; i < type.size / 2; ++i) {
      const unsigned char swap = buffer[i];
      buffer[i] = buffer[type.size - 1 - i];
      buffer[type.size - 1 - i] = swap;
    }
  }
  const auto as = [&buffer]<typename T>(T value) {
    std::memcpy(&value, buffer, sizeof value);
    return static_cast<double>(value);
  };
  switch (type.kind) {
    case ScalarKind::kFloat:
      return type.size == 8 ? as(double{}) : as(float{});
    case ScalarKind::kInt:
      switch (type.size) {
        case 1:
          return as(std::int8_t{});
        case 2:
          return as(std::int16_t{});
        case 4:
          return as(std::int32_t{});
        default:
          return as(std::int64_t{});
      }
    case ScalarKind::kUnsigned:
      switch (type.size) {
        case 1:
          return as(std::uint8_t{});
        case 2:
          return as(std::uint16_t{});
        case 4:
          return as(std::uint32_t{});
        default:
          return as(std::uint64_t{});
      }
  }
  return 0.0;
}

}  // namespace strata::io

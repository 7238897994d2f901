#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

// Fixed-width reads from packet bytes. Sensor packets are little-endian, network headers big-endian; the
// decoders call these for every return, so they are inline memcpy + swap rather than
// io::read_scalar (which dispatches on a runtime type and converts to double).
namespace strata::lidar {

template <typename T>
[[nodiscard]] inline T load(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof value);
  return value;
}

template <typename T>
[[nodiscard]] inline T byte_swapped(T value) {
  if constexpr (sizeof(T) == 1) {
    return value;
  } else if constexpr (sizeof(T) == 2) {
    return static_cast<T>(__builtin_bswap16(value));
  } else if constexpr (sizeof(T) == 4) {
    return static_cast<T>(__builtin_bswap32(value));
  } else {
    return static_cast<T>(__builtin_bswap64(value));
  }
}

template <typename T>
[[nodiscard]] inline T load_le(const std::uint8_t* bytes) {
  const T value = load<T>(bytes);
  return std::endian::native == std::endian::little ? value : byte_swapped(value);
}

template <typename T>
[[nodiscard]] inline T load_be(const std::uint8_t* bytes) {
  const T value = load<T>(bytes);
  return std::endian::native == std::endian::big ? value : byte_swapped(value);
}

}  // namespace strata::lidar

#pragma once

#include <cstdint>
#include <string_view>

namespace strata::api {

/// What a `Range` header asks of a resource of `size` bytes (RFC 9110, 14.2): the whole (no header, a
/// unit other than bytes, several ranges or a header that does not parse: a server may ignore those), one
/// range [first, last], or nothing it has (416).
struct ByteRange {
  enum class Kind { kWhole, kPart, kUnsatisfiable };
  Kind kind = Kind::kWhole;
  std::uint64_t first = 0;
  std::uint64_t last = 0;  ///< inclusive
};

/// `bytes=a-b`, `bytes=a-` and `bytes=-n` (the last n bytes).
[[nodiscard]] ByteRange parse_byte_range(std::string_view header, std::uint64_t size);

}  // namespace strata::api

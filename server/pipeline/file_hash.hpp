#pragma once

#include <string>
#include <string_view>

namespace strata::pipeline {

/// SHA-256 of `data` as 64 lowercase hex digits (OpenSSL's EVP): the map server's content hash, the one a
/// fleet's downloadMap checks (`mapHash`) and the map version's ETag.
[[nodiscard]] std::string sha256_hex(std::string_view data);

}  // namespace strata::pipeline

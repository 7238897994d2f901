#include "server/auth/operator_token.hpp"

#include <array>
#include <cstdint>
#include <random>

namespace strata::auth {

bool constant_time_equal(std::string_view given, std::string_view expected) {
  // Every byte of `expected` is looked at whatever `given` holds; the length difference is folded in too.
  auto difference = static_cast<unsigned>(given.size() ^ expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto a = i < given.size() ? static_cast<unsigned char>(given[i]) : 0U;
    difference |= a ^ static_cast<unsigned char>(expected[i]);
  }
  return difference == 0;
}

std::string generate_token() {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
  std::random_device device;
  std::string token;
  // 32 characters of 6 bits each: 192 bits, drawn 32 bits at a time.
  std::uint64_t bits = 0;
  int available = 0;
  while (token.size() < 32) {
    if (available < 6) {
      bits |= static_cast<std::uint64_t>(device()) << available;
      available += 32;
    }
    token.push_back(kAlphabet[bits & 63U]);
    bits >>= 6U;
    available -= 6;
  }
  return token;
}

bool is_valid_token(std::string_view token) {
  if (token.size() < 16 || token.size() > 128)
    return false;
  for (const char c : token) {
    const bool ok =
        (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    if (!ok)
      return false;
  }
  return true;
}

}  // namespace strata::auth

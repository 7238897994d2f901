// Native map files (load_mls_map, POST /api/v1/maps/{name}/load). A file's size field and FNV-1a checksum
// stop almost every mutation at the door, so when the first input byte is odd the harness "seals" the rest
// (writes the true size and appends the right checksum) and the mutations reach the tile decoder.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "core/mls/mls_file.hpp"

namespace {

std::uint64_t fnv1a64(const std::string& data) {
  std::uint64_t hash = 0xCBF29CE484222325ULL;
  for (const char c : data) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001B3ULL;
  }
  return hash;
}

constexpr std::size_t kSizeOffset = 12;  // after the magic (8) and the format version (4)

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1U) != 0 && bytes.size() >= kSizeOffset + sizeof(std::uint64_t)) {
    const std::uint64_t total = bytes.size() + sizeof(std::uint64_t);
    std::memcpy(bytes.data() + kSizeOffset, &total, sizeof(total));
    const std::uint64_t checksum = fnv1a64(bytes);
    bytes.append(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
  }
  try {
    const strata::MlsMap map = strata::deserialize_mls_map(bytes, "fuzz input");
    // What loads must save and load again to the same bytes.
    const std::string again = strata::serialize_mls_map(map);
    if (strata::serialize_mls_map(strata::deserialize_mls_map(again, "re-encoded")) != again)
      __builtin_trap();
  } catch (const strata::MlsFileError&) {
  }
  return 0;
}

// Simulator world files (strata serve --world FILE).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "drivers/sim/world/world_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    static_cast<void>(strata::sim::parse_world({reinterpret_cast<const char*>(data), size}, "fuzz.json"));
  } catch (const std::runtime_error&) {
  }
  return 0;
}

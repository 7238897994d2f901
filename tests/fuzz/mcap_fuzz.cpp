// MCAP files (strata serve --replay FILE.mcap): the reader checks the whole file and refuses what is cut
// short or damaged with an McapError; whatever it accepts, every message's bytes can be read.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>

#include "drivers/mcap/mcap_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto in = std::make_unique<std::istringstream>(std::string(reinterpret_cast<const char*>(data), size),
                                                 std::ios::binary);
  try {
    strata::mcap::McapReader reader(std::move(in), "fuzz.mcap");
    for (const strata::mcap::McapMessage& message : reader.messages()) {
      if (reader.message_data(message).size() != message.size)
        __builtin_trap();
    }
  } catch (const strata::mcap::McapError&) {
  }
  return 0;
}

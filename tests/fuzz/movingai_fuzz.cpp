// MovingAI benchmark maps and scenarios (strata plan, planner tests). The first byte picks the reader.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "drivers/io/map_file_error.hpp"
#include "drivers/io/movingai_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    if ((data[0] & 1U) == 0) {
      const strata::OccupancyGrid grid = strata::io::read_movingai_map(in, "fuzz.map");
      if (grid.cells.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height))
        __builtin_trap();
    } else {
      static_cast<void>(strata::io::read_movingai_scenario(in, "fuzz.scen"));
    }
  } catch (const strata::io::MapFileError&) {
  }
  return 0;
}

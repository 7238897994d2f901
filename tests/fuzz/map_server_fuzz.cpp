// ROS map_server maps: the YAML metadata and the PGM image (strata plan, planner tests). The first byte
// picks the reader and, for the image, the interpretation (trinary, scale or raw; negate).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "drivers/io/map_file_error.hpp"
#include "drivers/io/map_server_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), std::ios::binary);
  try {
    if ((data[0] & 1U) == 0) {
      static_cast<void>(strata::io::read_map_server_yaml(in, "/maps/fuzz.yaml"));
    } else {
      strata::io::MapServerMetadata metadata;
      metadata.resolution = 0.05;
      metadata.negate = (data[0] & 2U) != 0;
      metadata.mode = (data[0] & 4U) != 0 ? "raw" : (data[0] & 8U) != 0 ? "scale" : "trinary";
      const strata::OccupancyGrid grid = strata::io::read_map_server_image(in, "fuzz.pgm", metadata);
      if (grid.cells.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height))
        __builtin_trap();
    }
  } catch (const strata::io::MapFileError&) {
  }
  return 0;
}

// PCD point cloud files (strata register, strata map build, tests).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "drivers/io/pcd_reader.hpp"
#include "drivers/io/point_file_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::binary);
  try {
    const strata::io::LoadedCloud cloud = strata::io::read_pcd(in, "fuzz.pcd");
    for (const auto& p : cloud.points)
      if (!p.allFinite())
        __builtin_trap();  // the readers drop non-finite points
  } catch (const strata::io::PointFileError&) {
  }
  return 0;
}

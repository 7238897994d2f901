// 3DTK (slam6D) files: .3d scans, .pose and .frames poses. The first byte picks the reader.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "drivers/io/point_file_error.hpp"
#include "drivers/io/threedtk_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    switch (data[0] % 3) {
      case 0: {
        const strata::io::LoadedCloud cloud = strata::io::read_3dtk_scan(in, "fuzz.3d");
        for (const auto& p : cloud.points)
          if (!p.allFinite())
            __builtin_trap();
        break;
      }
      case 1:
        static_cast<void>(strata::io::read_3dtk_pose(in, "fuzz.pose"));
        break;
      default:
        static_cast<void>(strata::io::read_3dtk_frames(in, "fuzz.frames"));
        break;
    }
  } catch (const strata::io::PointFileError&) {
  }
  return 0;
}

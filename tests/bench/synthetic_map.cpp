// Writes a native map file of about --patches patches: a campus of blocks, each ground with a building of one
// or two storeys (outer walls with a door, an inner wall, floor slabs and a roof), a ramp up to a platform,
// a low fence and pillars. For benchmarking the clients on maps bigger than a simulator run makes in
// reasonable time (tests/browser/bench_render.mjs): the real MlsMap and the real file writer, so the server
// loads it like any saved map. Prints one JSON object.
// With --localizable 1 the file also holds localization data (the keyframes' points and poses a save of the
// pose graph writes: here the walls' tops and every third floor cell as points, a keyframe at each block's
// door), so a robot can be told to localize in it (VDA 5050 enableMap, --mode localize): for the fleet's
// map download-and-enable benchmark (tests/fleet/bench_map_download.mjs).
// Usage: strata_synthetic_map --patches 250000 --out campus.strata [--localizable 1]
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/localization/localization_map.hpp"
#include "core/mls/mls_file.hpp"
#include "core/mls/mls_map.hpp"

namespace strata {
namespace {

constexpr int kBlockCells = 128;  // 12.8 m: four tiles along a block's edge
constexpr int kBuildingX0 = 20;   // the building's footprint in the block, cells
constexpr int kBuildingX1 = 84;
constexpr int kBuildingY0 = 20;
constexpr int kBuildingY1 = 68;
constexpr int kDoorX0 = 48;  // a door in the building's south wall, cells
constexpr int kDoorX1 = 57;
constexpr int kInnerWallX = 52;  // splits each storey in two rooms
constexpr int kRampX0 = 96;      // a ramp rising north to a platform
constexpr int kRampX1 = 108;
constexpr int kRampY0 = 20;
constexpr int kRampY1 = 80;
constexpr int kPlatformY1 = 100;
constexpr float kStorey = 3.0F;        // m
constexpr float kDoorHeight = 2.1F;    // m
constexpr float kInnerWallTop = 2.8F;  // m: under the slab above
constexpr float kPlatform = 1.0F;      // m
constexpr float kFence = 1.0F;         // m

// A scanned floor is not flat to the millimetre: up to +-1 cm, fixed per cell, so that nothing drawing the
// map profits from a flatness real maps lack.
float roughness(CellIndex cell) {
  const auto hash =
      (static_cast<std::uint32_t>(cell.x) * 73856093U) ^ (static_cast<std::uint32_t>(cell.y) * 19349663U);
  return static_cast<float>(hash % 2001U) * 1e-5F - 0.01F;
}

MlsPatch horizontal(float z) {
  return {.mean = z, .variance = 1e-4F, .depth = 0.0F, .next = 0, .evidence = 8, .flags = 0};
}

MlsPatch vertical(float top, float depth) {
  return {.mean = top, .variance = 1e-4F, .depth = depth, .next = 0, .evidence = 8, .flags = 0};
}

/// Appends the patches of cell (cx, cy) of a block, lowest first; `storeys` is the block's building's.
/// Returns how many it appended.
int add_cell(MlsMap& map, CellIndex cell, int cx, int cy, int storeys) {
  int added = 0;
  const float noise = roughness(cell);
  const auto add = [&](MlsPatch patch) {
    if (!patch.vertical())
      patch.mean += noise;
    added += map.append_patch(cell, patch) ? 1 : 0;
  };
  const float roof = static_cast<float>(storeys) * kStorey;
  const bool in_building = cx >= kBuildingX0 && cx < kBuildingX1 && cy >= kBuildingY0 && cy < kBuildingY1;
  const bool outer_wall = in_building && (cx == kBuildingX0 || cx == kBuildingX1 - 1 || cy == kBuildingY0 ||
                                          cy == kBuildingY1 - 1);
  if (outer_wall) {
    if (cy == kBuildingY0 && cx >= kDoorX0 && cx < kDoorX1) {
      add(horizontal(0.0F));
      add(vertical(roof, roof - kDoorHeight));  // the wall above the door
    } else {
      add(vertical(roof, roof));
    }
    return added;
  }
  if (in_building) {
    for (int storey = 0; storey < storeys; ++storey) {
      const float floor = static_cast<float>(storey) * kStorey;
      add(horizontal(floor));
      if (cx == kInnerWallX)
        add(vertical(floor + kInnerWallTop, kInnerWallTop - 0.05F));
    }
    add(horizontal(roof));
    return added;
  }
  if (cx >= kRampX0 && cx < kRampX1 && cy >= kRampY0 && cy < kPlatformY1) {
    const bool edge = cx == kRampX0 || cx == kRampX1 - 1;
    const float rise =
        cy < kRampY1 ? kPlatform * static_cast<float>(cy - kRampY0) / (kRampY1 - kRampY0) : kPlatform;
    if (edge && rise > 0.2F)
      add(vertical(rise, rise));  // the ramp's side, a step down to the ground
    else
      add(horizontal(rise));
    return added;
  }
  const bool fence = cy == 2 && cx >= 8 && cx < kBlockCells - 8;
  const bool pillar = (cx % 32 >= 12 && cx % 32 < 15) && (cy >= 108 && cy < 111);
  if (fence)
    add(vertical(kFence, kFence));
  else if (pillar)
    add(vertical(2.5F, 2.5F));
  else
    add(horizontal(0.0F));
  return added;
}

long parse_long(std::string_view text, const char* what) {
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || value <= 0) {
    std::fprintf(stderr, "strata_synthetic_map: %s must be a positive number\n", what);
    std::exit(2);
  }
  return value;
}

/// Points a keyframe would hold of cell `cell`: the tops of its walls, every third floor cell's ground.
void add_localization_points(const MlsMap& map, CellIndex cell, LocalizationMap& localization) {
  const Eigen::Vector2d centre = map.cell_center(cell);
  const auto patches = map.patches(cell);
  for (const MlsPatch& patch : patches) {
    if (patch.vertical() || (cell.x % 3 == 0 && cell.y % 3 == 0)) {
      localization.points.emplace_back(static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                                       patch.mean);
    }
  }
}

int run(int argc, char** argv) {
  long wanted = 250000;
  bool localizable = false;
  std::filesystem::path out;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string_view name = argv[i];
    if (name == "--patches")
      wanted = parse_long(argv[i + 1], "--patches");
    else if (name == "--out")
      out = argv[i + 1];
    else if (name == "--localizable")
      localizable = std::string_view(argv[i + 1]) == "1";
  }
  if (out.empty()) {
    std::fprintf(stderr, "usage: strata_synthetic_map --patches N --out FILE\n");
    return 2;
  }
  // About a square of blocks (a block holds about 20 400 patches), as many rows as it takes; the last block
  // is cut off after the row of cells that reaches the count.
  const int columns =
      std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(wanted) / 20400.0))));
  MlsMap map;
  LocalizationMap localization;
  long patches = 0;
  int blocks = 0;
  for (; patches < wanted; ++blocks) {
    const int bx = blocks % columns;
    const int by = blocks / columns;
    const int storeys = 1 + (bx + 2 * by) % 2;
    for (int cy = 0; cy < kBlockCells && patches < wanted; ++cy) {
      for (int cx = 0; cx < kBlockCells; ++cx) {
        const CellIndex cell{bx * kBlockCells + cx, by * kBlockCells + cy};
        patches += add_cell(map, cell, cx, cy, storeys);
        if (localizable)
          add_localization_points(map, cell, localization);
      }
    }
    Eigen::Isometry3d door = Eigen::Isometry3d::Identity();  // in front of the building's door
    door.translation() = Eigen::Vector3d((bx * kBlockCells + (kDoorX0 + kDoorX1) / 2) * map.resolution(),
                                         (by * kBlockCells + kBuildingY0 - 5) * map.resolution(), 0.0);
    localization.keyframe_poses.push_back(door);
  }
  for (const TileIndex tile : map.tile_indices())
    map.set_tile_version(tile, 1);
  map.set_version(1);
  if (localizable)
    save_map_file(map, &localization, out);
  else
    save_mls_map(map, out);
  // The campus covers [0, size_x] x [0, size_y] metres.
  const double block = kBlockCells * map.resolution();
  const int rows = (blocks + columns - 1) / columns;
  std::printf(
      "{\"patches\": %zu, \"tiles\": %zu, \"blocks\": %d, \"size_m\": [%.1f, %.1f], \"file\": \"%s\"}\n",
      map.patch_count(), map.tile_count(), blocks, std::min(blocks, columns) * block, rows * block,
      out.c_str());
  return 0;
}

}  // namespace
}  // namespace strata

int main(int argc, char** argv) {
  return strata::run(argc, argv);
}

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/mls/mls_patch.hpp"

namespace strata {

// 32 x 32 cells (3.2 m at 0.1 m): small enough that the 2 KB of cell heads per tile stay cheap in sparse
// outdoor maps (measured: 47 bytes per occupied cell on the 3DTK scans with 32, 58 with 64), large enough
// that a scan touches a few hundred tiles.
inline constexpr int kMlsTileBits = 5;
inline constexpr int kMlsTileSize = 1 << kMlsTileBits;  ///< cells along a tile's edge
inline constexpr int kMlsTileCells = kMlsTileSize * kMlsTileSize;

/// A square of kMlsTileSize^2 cells: the unit of storage, change tracking, streaming and persistence.
/// Each cell is a height-sorted singly linked list of patches in one pool per tile, addressed by 16-bit
/// handles (index + 1; 0 = none). That costs 2 bytes per cell plus 16 per patch, instead of a vector per
/// cell (24 bytes + a heap block each), which is what keeps the map near 20 bytes per occupied cell.
struct MlsTile {
  using Handle = std::uint16_t;
  static constexpr std::size_t kMaxPatches = 65535;

  std::array<Handle, kMlsTileCells> first{};  ///< each cell's lowest patch
  std::vector<MlsPatch> pool;
  Handle free_list = 0;  ///< released pool slots, chained through `next`
  std::uint64_t version = 0;

  [[nodiscard]] MlsPatch& at(Handle handle) { return pool[handle - 1U]; }
  [[nodiscard]] const MlsPatch& at(Handle handle) const { return pool[handle - 1U]; }

  /// A pool slot holding `patch`, or 0 when the pool is full (then the caller drops the point).
  [[nodiscard]] Handle allocate(const MlsPatch& patch) {
    if (free_list != 0) {
      const Handle handle = free_list;
      free_list = at(handle).next;
      at(handle) = patch;
      return handle;
    }
    if (pool.size() >= kMaxPatches)
      return 0;
    pool.push_back(patch);
    return static_cast<Handle>(pool.size());
  }

  void release(Handle handle) {
    at(handle) = MlsPatch{};
    at(handle).next = free_list;
    free_list = handle;
  }

  /// Calls f(const MlsPatch&) for the patches of cell `index` (local, row-major), lowest first.
  template <typename F>
  void for_each_patch(int index, F&& f) const {
    for (Handle h = first[static_cast<std::size_t>(index)]; h != 0; h = at(h).next)
      f(at(h));
  }
};

}  // namespace strata

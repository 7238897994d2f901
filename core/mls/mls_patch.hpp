#pragma once

#include <cstdint>

namespace strata {

/// One surface in an MLS cell: a horizontal patch (depth 0) at height `mean`, or a vertical patch
/// (depth > 0) reaching from `mean` down to `mean - depth`. 16 bytes: floats are ample for heights known to
/// millimetres, and the cell's patches are chained through `next` inside their tile's pool.
struct MlsPatch {
  float mean = 0.0F;          ///< height of the surface (the top of a vertical patch), metres
  float variance = 0.0F;      ///< of `mean`, m^2
  float depth = 0.0F;         ///< 0: horizontal; > 0: vertical, reaching this far below `mean`
  std::uint16_t next = 0;     ///< handle of the next higher patch in the cell, 0 = none (pool-internal)
  std::uint8_t evidence = 0;  ///< hits minus pass-through rays, saturating; removed at 0
  std::uint8_t flags = 0;     ///< kDriven, ...

  /// The robot stood on this surface (MlsMap::mark_driven): ground its wheels found, whether or not a
  /// scanner saw it. Traversable whatever the neighbours suggest.
  static constexpr std::uint8_t kDriven = 1U;
  /// The robot's centre passed over this surface: its track, the line it drove along (always driven too).
  /// The robot fitted there, so it may drive back along it whatever lower ground was seen beside it
  /// (PatchGraph::passable).
  static constexpr std::uint8_t kTrack = 2U;
  static constexpr std::uint8_t kKnownFlags = kDriven | kTrack;

  [[nodiscard]] bool vertical() const { return depth > 0.0F; }
  [[nodiscard]] bool driven() const { return (flags & kDriven) != 0; }
  [[nodiscard]] bool on_track() const { return (flags & kTrack) != 0; }
  [[nodiscard]] float top() const { return mean; }
  [[nodiscard]] float bottom() const { return mean - depth; }
};
static_assert(sizeof(MlsPatch) == 16);

}  // namespace strata

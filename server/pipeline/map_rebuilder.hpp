#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/localization/keyframe.hpp"
#include "core/mls/mls_map.hpp"

namespace strata::pipeline {

struct MapRebuildOptions {
  /// A keyframe moved when a pose graph optimization shifted it this far from where the map has it,
  /// metres (half a cell: less does not change which cell a point falls in, on average)...
  double min_shift = 0.05;
  /// ...or turned it this much, radians (the same shift at 10 m from the sensor).
  double min_turn = 0.005;
};

/// How far the keyframes are from where the map has them.
struct KeyframeMoves {
  std::size_t keyframes = 0;
  std::size_t moved = 0;       ///< keyframes that moved beyond the options' thresholds
  double largest_shift = 0.0;  ///< metres, the largest move of a keyframe's origin
};

/// Makes the map follow the pose graph (docs/architecture.md 4.1, "the map follows"): when an
/// optimization moved keyframes from where the map has them, builds the map anew from every keyframe at
/// its corrected pose, oldest first, the way the live map was built (rays first, then points). Knows
/// where the map has each keyframe: where the scan path put it, until a rebuild it took part in landed.
class MapRebuilder {
 public:
  explicit MapRebuilder(MlsConfig config, MapRebuildOptions options = {});

  /// Which of `keyframes` moved from where the map has them: a rebuild is due when any did.
  [[nodiscard]] KeyframeMoves moves(const std::vector<KeyframePose>& keyframes) const;
  /// The map from `keyframes` at their poses. Call landed() once it is in use.
  [[nodiscard]] MlsMap build(const std::vector<KeyframePose>& keyframes) const;
  /// `keyframes` are in the map at these poses now.
  void landed(const std::vector<KeyframePose>& keyframes);

 private:
  [[nodiscard]] const Eigen::Isometry3d& in_map(const KeyframePtr& keyframe) const;

  MlsConfig config_;
  MapRebuildOptions options_;
  std::unordered_map<KeyframePtr, Eigen::Isometry3d> rebuilt_at_;
};

}  // namespace strata::pipeline

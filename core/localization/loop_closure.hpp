#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <span>
#include <vector>

#include "core/localization/keyframe.hpp"
#include "core/posegraph/pose_graph.hpp"
#include "core/registration/register_scan.hpp"

namespace strata {

struct LoopClosureOptions {
  /// Keyframes this far apart along the way, metres, and no nearer: the scan-to-map localizer already
  /// ties neighbours together.
  double min_travel = 15.0;
  /// Where to look: older keyframes within this of the new one's estimated position, metres, widened by
  /// `drift_allowance` per metre driven between them (the estimate may have drifted that far), up to
  /// max_search_radius.
  double search_radius = 3.0;
  double drift_allowance = 0.03;
  double max_search_radius = 8.0;
  /// What a match may move the new keyframe from its estimate, metres: this plus `drift_allowance` per
  /// metre driven between the two keyframes (up to max_search_radius); farther it slid, it did not find
  /// drift. On the campus bridge deck, 35 m after the keyframe it matched, a lidar keyframe whose estimate
  /// was 0.13 m off was matched 3.2 m along the deck (docs/benchmarks.md, "Loops on the bridge deck").
  double min_drift = 0.5;
  /// Levels apart are not one place (a bridge deck over the road): candidates differ in estimated height
  /// by at most this, metres.
  double max_height_difference = 1.0;
  /// Keyframes on each side of the candidate joined into the target submap.
  int submap_keyframes = 3;
  /// How hard a match must be to count as a loop: the registration's fault check with these limits,
  /// plus an RMSE bound stricter than the scan path's (a loop edge moves the whole map).
  RegistrationOptions registration = default_registration();
  /// The match finished point-to-plane from where that left it, and kept if it moves it no more than
  /// `max_polish_translation` (metres) and `max_polish_rotation` (radians, 2 degrees).
  RegistrationOptions polish = default_polish();
  double max_polish_translation = 0.3;
  double max_polish_rotation = 0.035;
  /// metres and radians: the standard deviation of a loop edge in its well-constrained directions.
  /// 0.1 m rather than 0.05: keyframes thinned to 0.2 m match within about that, and a stiffer loop let one
  /// biased early match pull the campus run further (max error 3.4 m against 2.4 m).
  double sigma_translation = 0.1;
  double sigma_rotation = 0.01;
  /// Below this normalised eigenvalue a direction gets proportionally less information (a corridor's
  /// axis): what the match did not see it does not claim. The scan path's guard (0.08, since the bridge
  /// deck's 0.048-0.056): at 0.05 the campus tilting run dropped 63 loops as outliers (3 at 0.08) and its
  /// rebuilt map's revisit spread p95 was 0.56 m (0.39 m; docs/benchmarks.md, "Far floor").
  double weak_direction = 0.08;

  static RegistrationOptions default_registration();
  static RegistrationOptions default_polish();
};

/// A verified loop closure: where keyframe `to` (the newer) is seen from keyframe `from`.
struct LoopClosure {
  PoseGraphEdge edge;
  double rmse = 0.0;
  double correction = 0.0;  ///< metres between the estimate and the match: the drift it found
};

/// Looks for a loop closure of keyframe `newest` (docs/architecture.md 4.1): the nearest older keyframe
/// within the search radius of its estimated pose, far enough back along the way; registers the newest's
/// points onto a submap of that keyframe and its neighbours at their estimated poses, from the estimate,
/// coarse to fine and with the fine stage alone, and takes the better fit; keeps the match only when the
/// fault check accepts it and it moved the newest no further than the estimate can have drifted. `poses` are
/// the current estimates, one per keyframe.
/// `edges`: the graph's edges so far; its loops shorten the way between the newest and older keyframes,
/// and with it how far the estimate can have drifted (way_between).
[[nodiscard]] std::optional<LoopClosure> find_loop_closure(const std::vector<KeyframePtr>& keyframes,
                                                           const std::vector<Eigen::Isometry3d>& poses,
                                                           std::size_t newest,
                                                           std::span<const PoseGraphEdge> edges = {},
                                                           const LoopClosureOptions& options = {});

/// The way driven between keyframes `older` and `newer`, metres, along the chain or through one loop
/// edge (the chain to one end of the loop, the chain from its other end): what their estimates can have
/// drifted apart. Once a loop has tied the robot to the map, the drift since is the way driven since that
/// loop, not since the older keyframe was made.
[[nodiscard]] double way_between(const std::vector<KeyframePtr>& keyframes,
                                 std::span<const PoseGraphEdge> edges, std::size_t older, std::size_t newer);

/// Information of a relative pose measured by point-to-plane registration: its well-constrained
/// directions at 1/sigma^2, weak ones scaled down by their eigenvalue (below `weak`). The constraint's
/// directions are in the registration's target frame; the edge's translation error is in the frame of
/// `from` and its rotation error in that of `to` (their rotations in the target frame).
[[nodiscard]] PoseInformation registration_information(const TranslationConstraint& constraint,
                                                       const Eigen::Matrix3d& from_rotation,
                                                       const Eigen::Matrix3d& to_rotation,
                                                       double sigma_translation, double sigma_rotation,
                                                       double weak);

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/localization/localization_map.hpp"
#include "core/localization/pose_estimate.hpp"
#include "core/localization/relocalizer.hpp"
#include "core/localization/scan_to_map_localizer.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// What one search for the robot did, for the status and the log.
struct RelocalizationReport {
  enum class Search {
    kHint,      ///< around an operator's estimate
    kFollow,    ///< the places that fitted as well, judged by a later scan
    kWholeMap,  ///< lost: everywhere the map's robot drove
    kCheck,     ///< a place taken, confirmed or contradicted by the scans after it
  };
  Search search = Search::kHint;
  double stamp = 0.0;  ///< of the scan it searched with
  bool found = false;
  std::string message;
  std::size_t candidates = 0;
  double seconds = 0.0;
};

/// What the scans after a place was taken said of it.
enum class PlacementCheck {
  kNone,          ///< no place waits for confirmation
  kPending,       ///< not enough scans yet
  kConfirmed,     ///< the next scans matched from there
  kContradicted,  ///< the next scans were refused from there: the place was wrong
};

/// Finding the robot in a saved map over several scans (docs/architecture.md 4.1, "Finding the robot"):
/// around an operator's estimate, in the whole map while lost, and the places that fit a scan as well
/// followed as the robot drives on, until one scan tells them apart. A place taken is the robot's pose
/// only once the next scans match from it: a search that fits a wrong place (a deck's railings a few
/// metres along) would otherwise hold the robot there, every right match then refused as a jump. Scan
/// path only; the Localizer calls it.
class RelocalizationTracker {
 public:
  explicit RelocalizationTracker(std::shared_ptr<const LocalizationMap> map,
                                 RelocalizationOptions options = {});

  [[nodiscard]] const RelocalizationOptions& options() const { return relocalizer_.options(); }

  /// Searches around `hint` (the robot's pose when it took `points`, base frame, at `odometry`). Found:
  /// where to place the robot. Not found: its places, if any, are followed by the next scans.
  [[nodiscard]] std::optional<Eigen::Isometry3d> search_around(const PoseEstimate& hint,
                                                               const PointCloud& points,
                                                               const std::optional<Pose2>& odometry,
                                                               double stamp);
  /// Before a scan registers: the places followed, carried by the odometry since and judged by this scan
  /// once the robot has moved a little. Found: where to place the robot.
  [[nodiscard]] std::optional<Eigen::Isometry3d> follow(const PointCloud& points,
                                                        const std::optional<Pose2>& odometry, double stamp);
  /// After a scan registered while the localization is lost: the whole map is searched at the first lost
  /// scan and every RelocalizationOptions::lost_search_every after, unless places are being followed.
  [[nodiscard]] std::optional<Eigen::Isometry3d> search_while_lost(const PointCloud& points,
                                                                   const std::optional<Pose2>& odometry,
                                                                   double stamp);
  /// Not lost (any more): the next lost scan searches at once.
  void not_lost() { lost_scans_ = 0; }

  /// A place was taken at the scan of `stamp`: the scans after it confirm or contradict it.
  void placed(double stamp);
  /// After each scan registered (stamp `stamp`): what it says of a place taken before it.
  PlacementCheck check_placement(const LocalizationUpdate& update, double stamp);

  /// What the searches since the last call did, oldest first.
  [[nodiscard]] std::vector<RelocalizationReport> take_reports() { return std::exchange(reports_, {}); }

 private:
  /// Places a search found fitting as well, for the next scans to decide between.
  struct Following {
    std::vector<Eigen::Isometry3d> places;  // map frame, at the scan of `odometry`
    Pose2 odometry;
    std::size_t scans = 0;  // followed so far
    double metres = 0.0;    // driven between them
  };
  /// A place taken, waiting for the scans after it.
  struct Unconfirmed {
    double stamp = 0.0;  // of the scan it was found with
    std::size_t matched = 0;
    std::size_t refused = 0;
  };
  void report(RelocalizationReport::Search search, double stamp, const RelocalizationResult& found,
              std::string message);

  Relocalizer relocalizer_;
  std::optional<Following> following_;
  std::optional<Unconfirmed> unconfirmed_;
  std::size_t lost_scans_ = 0;  // in a row, while lost
  std::vector<RelocalizationReport> reports_;
};

}  // namespace strata

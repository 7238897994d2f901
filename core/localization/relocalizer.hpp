#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/ann/growing_kdtree.hpp"
#include "core/localization/localization_map.hpp"
#include "core/points/point_cloud.hpp"
#include "core/points/voxel_key_map.hpp"
#include "core/registration/normals.hpp"
#include "core/registration/register_scan.hpp"

namespace strata {

struct RelocalizationOptions {
  /// Around a hint: positions this far from it, metres, every `position_step`; headings this far either
  /// side of its heading, radians, every `yaw_step`. Without a hint: every keyframe's place (where the
  /// robot that made the map drove), at every `yaw_step` all round.
  double hint_radius = 2.0;
  double hint_yaw = 0.55;  // a little over 30 degrees
  double position_step = 0.5;
  double yaw_step = 0.175;  // 10 degrees
  /// Scoring a candidate: the scan thinned to one point per `score_voxel`, and the share of those whose
  /// voxel of `hit_voxel` holds a map point. Cheap: a hash lookup per point, so thousands of candidates
  /// take milliseconds; ICP then refines only the best `refined` of them.
  double score_voxel = 0.5;
  double hit_voxel = 0.3;
  std::size_t refined = 6;
  /// The refinement is the scan path's registration with its source thinned to this at both stages: with
  /// the scan path's 0.2 m fine stage a yard scan fitted its mirror image 9 m away nearly as well (98 and
  /// 93 % of its walls) and was refused as ambiguous (docs/benchmarks.md, "Finding the robot").
  double refinement_source_voxel = 0.3;
  /// And a last stage with the source at this, run to a standstill (relocalizer.cpp, refinement).
  double polish_source_voxel = 0.2;
  /// Accepting the best refined candidate: this share of its points paired within ICP's fine bound at
  /// an RMSE below `max_rmse`, and no other refined candidate elsewhere (more than `distinct_metres` or
  /// `distinct_radians` away) within `ambiguity_margin` of its share: two places that fit as well are not
  /// told apart by guessing.
  double min_inlier_share = 0.55;
  double max_rmse = 0.12;
  double distinct_metres = 0.2;
  double distinct_radians = 0.35;
  /// Telling refined candidates apart: by the scan's structure alone (points `structure_height` above
  /// the ground the robot stands on, thinned to `structure_voxel`), the share within `tight_distance` of
  /// a map point. The ground fits anywhere at any heading, and within ICP's 0.25 m bound a hallway fits
  /// 100 % a metre along itself; the walls' and doors' centimetres tell where. The best is taken when it
  /// holds `min_structure_share`, no candidate elsewhere comes within `ambiguity_margin` of it, and the
  /// scan has `min_structure_points` to judge by.
  /// And where the map covers the scan's structure (a map point within `covered_distance`), it must fit
  /// closely: `min_covered_structure_share` of that part within tight_distance of the map. A place 0.4 m
  /// along a path held 89 % of its structure and right finds 93-100 %; but a map of the robot's first
  /// seconds lacks walls it sees later, and the right place held 81 % of all of a scan's structure there
  /// (docs/benchmarks.md, "Finding the robot").
  double structure_height = 0.3;
  double structure_voxel = 0.2;
  double tight_distance = 0.1;
  double min_structure_share = 0.75;
  double covered_distance = 1.0;
  double min_covered_structure_share = 0.9;
  /// That share is of the map's surfaces, not only its points: a map of one scan has points 0.15-0.2 m
  /// apart on far walls, and a scan's points between them are up to 0.1 m from the nearest (the browser
  /// test's map of the first seconds: 82 % by points). A point whose nearest map point is within
  /// `surface_reach` is also near when it lies within tight_distance / 2 of that point's surface (the
  /// registration's normals, LazyNormals). Ranking candidates by surfaces too made more of them fit as
  /// well (campus hint 49 -> 41 % right).
  double surface_reach = 0.2;
  double ambiguity_margin = 0.05;
  std::size_t min_structure_points = 30;
  /// Following places that fit as well as the robot drives on (done by the caller: the server's
  /// localizer, the relocalization bench): they are given up once it has driven `follow_metres`, the
  /// length of the campus's featureless hallway (campus, a hint then the next scans: 10 m 66 %, 20 m 70 %,
  /// 30 m 81 %, 50 m 86 % right, 3 % wrong throughout; docs/benchmarks.md, "Finding the robot"). A lost
  /// robot with no places to follow is searched for in the whole map at its first lost scan and every
  /// `lost_search_every` scans after (a search takes 0.1-2.5 s; a tilting scanner's 5 scans are 10 m).
  double follow_metres = 50.0;
  std::size_t lost_search_every = 5;
  /// A place followed is taken only when a scan's fit leaves it within this of where the odometry
  /// carried it (Relocalizer::follow).
  double settled_metres = 0.1;
  double settled_radians = 0.035;  // 2 degrees
  /// A place taken is confirmed when this many of the scans after it match from there, and dropped
  /// (the robot lost, the whole map searched) when this many are refused from there first: a right
  /// place's next scans match, a wrong one's are refused as jumps or poor fits.
  std::size_t confirm_scans = 2;
  std::size_t contradict_scans = 2;
  /// A place about to be taken is refined again from starts this far to each side of it (metres, along
  /// and across its heading), for a better basin near it (relocalizer.cpp, decide); 0: not.
  double basin_step = 0.3;
};

/// What a search found, and why not when it did not.
struct RelocalizationResult {
  bool found = false;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< base in the map frame, when found
  double inlier_share = 0.0;                               ///< of the best refined candidate
  double rmse = 0.0;
  double structure_share = 0.0;          ///< of the best refined candidate
  double covered_structure_share = 0.0;  ///< of its structure that the map covers
  std::size_t candidates = 0;            ///< poses scored
  double seconds = 0.0;
  std::string message;  ///< plain words: where it was found, or why not
  /// When places fit as well: each of them (the best first), for the next scans to decide between
  /// (`Relocalizer::follow`, with the odometry since); empty otherwise.
  std::vector<Eigen::Isometry3d> places;
  /// Whether a candidate was refined: `pose` is then the best one, found or not.
  bool refined = false;

  /// Where the next scans are to look after a search around a hint that did not find the robot: the
  /// places that fit as well, or the best refined candidate where none fitted well enough (the map lacks
  /// walls the scan sees there, or the scan sees too little). `Relocalizer::follow` judges it with each
  /// later scan, and searches the whole map when it fits none.
  [[nodiscard]] std::vector<Eigen::Isometry3d> places_to_follow() const {
    if (found)
      return {};
    if (places.empty() && refined)
      return {pose};
    return places;
  }
};

/// Finding the robot in a saved map (issue 22): around an operator's hint, or anywhere. Candidate poses
/// are scored cheaply by how many of the scan's points land on the map, the best few refined by ICP against
/// the whole map, and the best of those accepted only if it fits well and no other place fits as well.
/// Not thread-safe (the registration keeps its normals); one per thread.
class Relocalizer {
 public:
  explicit Relocalizer(std::shared_ptr<const LocalizationMap> map, RelocalizationOptions options = {});

  [[nodiscard]] const RelocalizationOptions& options() const { return options_; }

  /// `scan` in the base frame (cleaned, as the localizer takes it); the hint's heading `yaw` and position
  /// in the map frame; `z` its height, or none: the height of the nearest keyframe (the level the robot
  /// that made the map drove there).
  [[nodiscard]] RelocalizationResult around(const PointCloud& scan, double x, double y, double yaw,
                                            std::optional<double> z = std::nullopt);
  /// The same without a hint: every place a keyframe was.
  [[nodiscard]] RelocalizationResult anywhere(const PointCloud& scan);
  /// Deciding between places that fit a scan as well (RelocalizationResult::places) with a later scan:
  /// `places` are where each would put the robot now (moved by the odometry since). One scan of a hallway
  /// fits a metre along it as well; the scans the robot takes as it drives on see a door or an end. The
  /// place left is taken only if this scan's fit leaves it where the odometry carried it (within
  /// settled_metres; else it is followed on from where this scan put it) and a search around it (as
  /// `around`) agrees; otherwise that search's places are the ones to follow on. A scan of bare ground only
  /// drops the places it does not fit. A scan that fits none of them (all were wrong) is searched for in the
  /// whole map (as `anywhere`), and that search's places are the ones to follow on.
  [[nodiscard]] RelocalizationResult follow(const PointCloud& scan,
                                            const std::vector<Eigen::Isometry3d>& places);

 private:
  struct Candidate {
    Eigen::Isometry3d pose;
    double score = 0.0;
  };
  [[nodiscard]] double score(const PointCloud& thinned, const Eigen::Isometry3d& pose) const;
  /// The scan's structure: its points structure_height above the ground, thinned to structure_voxel.
  [[nodiscard]] PointCloud structure_of(const PointCloud& scan) const;
  /// How `structure` (base frame) fits the map at `pose`: the share of all of it within tight_distance of
  /// a map point (what candidates are ranked by), and of the part with a map point within
  /// covered_distance, the share within tight_distance of the map's points or surfaces (what a place
  /// needs to be taken).
  struct StructureFit {
    double share = 0.0;
    double covered_share = 0.0;
  };
  [[nodiscard]] StructureFit structure_fit(const PointCloud& structure, const Eigen::Isometry3d& pose);
  /// Whether `point` (map frame) lies on the surface of its nearest map point `nearest`
  /// (RelocalizationOptions::surface_reach).
  [[nodiscard]] bool on_surface(const Eigen::Vector3d& point, const Neighbor& nearest);
  /// Refines each candidate by ICP and takes the best if it fits and no other place fits as well.
  [[nodiscard]] RelocalizationResult decide(const PointCloud& scan, const PointCloud& structure,
                                            const std::vector<Candidate>& candidates);
  /// Refuses a find or a place to follow outside the hint's radius and heading span (what the operator
  /// was told is searched).
  void keep_within_hint(RelocalizationResult& result, double x, double y, double yaw) const;
  /// `hinted`: the poses are around an operator's hint (a scan of bare ground is searched only there).
  [[nodiscard]] RelocalizationResult search(const PointCloud& scan, std::vector<Eigen::Isometry3d> poses,
                                            bool hinted);

  std::shared_ptr<const LocalizationMap> map_;
  RelocalizationOptions options_;
  VoxelKeyMap hits_;     // the map's voxels of hit_voxel
  GrowingKdTree tree_;   // the map's points, for structure_fit
  LazyNormals normals_;  // their surfaces, estimated as structure_fit asks
  ScanRegistration registration_;
};

}  // namespace strata

#include "core/localization/relocalizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <utility>

#include "core/geometry/angles.hpp"
#include "core/geometry/pose.hpp"
#include "core/localization/scan_to_map_localizer.hpp"
#include "core/points/voxel_downsample.hpp"
#include "core/points/voxel_key.hpp"

namespace strata {
namespace {

/// A base at `position` standing on ground whose up is `up` (map frame), heading `yaw`: the base's z along
/// `up`, its x the heading's direction laid onto that ground. On the bridge's 5.7 degree ramp a level
/// candidate put the scan's points 8 m ahead 0.8 m off the ramp, and no candidate there was refined into
/// the right place (docs/benchmarks.md, "Finding the robot": on the ramp's tilt).
Eigen::Isometry3d pose_on(const Eigen::Vector3d& position, const Eigen::Vector3d& up, double yaw) {
  const Eigen::Vector3d z = up.normalized();
  const Eigen::Vector3d heading(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d x = (heading - heading.dot(z) * z).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = z.cross(x);
  pose.linear().col(2) = z;
  pose.translation() = position;
  return pose;
}

/// The ground's up under a keyframe: its base's z axis (the robot that made the map stood on it).
Eigen::Vector3d ground_up(const Eigen::Isometry3d& keyframe) {
  const Eigen::Vector3d up = keyframe.linear().col(2);
  // A keyframe tipped past 60 degrees is no ground to stand a candidate on: level instead.
  return up.z() > 0.5 ? up : Eigen::Vector3d::UnitZ();
}

/// The registration the localizer uses, judged by nothing but its fit: the candidates are up to a step
/// apart from where the robot is, which the scan path's jump limits would refuse.
RegistrationOptions refinement(const RelocalizationOptions& relocalization) {
  RegistrationOptions options = LocalizerOptions::default_registration();
  options.limits.max_translation_jump = std::numeric_limits<double>::infinity();
  options.limits.max_rotation_jump = std::numeric_limits<double>::infinity();
  // Every stage at the full budget: a candidate's coarse stage has farther to go than a tracked scan's,
  // for which the scan path's budget was measured (docs/benchmarks.md, "The coarse stage's budget").
  for (RegistrationStage& stage : options.stages) {
    stage.source_voxel_size = relocalization.refinement_source_voxel;
    stage.max_source_points = 0;
  }
  // The scan path's stages stop when a step improves the fit by little, which along a hallway or a deck's
  // railings is every step: candidates a metre apart stayed apart and fitted as well. A last stage run
  // until the steps are a tenth of a millimetre brings them to where the few walls and ends that tell
  // the place pull them (docs/benchmarks.md, "Finding the robot").
  RegistrationStage polish = options.stages.back();
  polish.source_voxel_size = relocalization.polish_source_voxel;
  polish.mse_change_threshold = 0.0;
  polish.min_step_translation = 1e-4;
  polish.min_step_rotation = 1e-5;
  polish.max_iterations = 100;
  options.stages.push_back(polish);
  return options;
}

}  // namespace

Relocalizer::Relocalizer(std::shared_ptr<const LocalizationMap> map, RelocalizationOptions options)
    : map_(std::move(map)),
      options_(options),
      hits_(map_->points.size()),
      tree_(map_->cloud()),
      normals_(tree_),
      registration_(refinement(options_)) {
  const double inverse = 1.0 / options_.hit_voxel;
  for (const Eigen::Vector3f& p : map_->points)
    hits_.try_emplace(voxel_key(voxel_cell(p.cast<double>(), inverse)), 1);
  registration_.set_thinned_target(map_->cloud());
}

double Relocalizer::score(const PointCloud& thinned, const Eigen::Isometry3d& pose) const {
  const double inverse = 1.0 / options_.hit_voxel;
  std::size_t hits = 0;
  for (const Eigen::Vector3d& p : thinned)
    hits += hits_.find(voxel_key(voxel_cell(pose * p, inverse))) != nullptr ? 1 : 0;
  return thinned.empty() ? 0.0 : static_cast<double>(hits) / static_cast<double>(thinned.size());
}

PointCloud Relocalizer::structure_of(const PointCloud& scan) const {
  PointCloud structure;
  for (const Eigen::Vector3d& p : scan)
    if (p.z() > options_.structure_height)
      structure.push_back(p);
  return voxel_downsample(structure, options_.structure_voxel);
}

Relocalizer::StructureFit Relocalizer::structure_fit(const PointCloud& structure,
                                                     const Eigen::Isometry3d& pose) {
  const double tight_squared = options_.tight_distance * options_.tight_distance;
  std::size_t near = 0;
  std::size_t covered = 0;
  std::size_t on_map = 0;
  for (const Eigen::Vector3d& p : structure) {
    const Eigen::Vector3d point = pose * p;
    const auto neighbor = tree_.nearest(point, options_.covered_distance);
    if (!neighbor)
      continue;
    ++covered;
    const bool close = neighbor->squared_distance <= tight_squared;
    near += close ? 1 : 0;
    on_map += close || on_surface(point, *neighbor) ? 1 : 0;
  }
  StructureFit fit;
  if (!structure.empty())
    fit.share = static_cast<double>(near) / static_cast<double>(structure.size());
  if (covered > 0)
    fit.covered_share = static_cast<double>(on_map) / static_cast<double>(covered);
  return fit;
}

bool Relocalizer::on_surface(const Eigen::Vector3d& point, const Neighbor& nearest) {
  if (nearest.squared_distance > options_.surface_reach * options_.surface_reach)
    return false;
  const Eigen::Vector3d* normal = normals_.at(nearest.index);
  return normal != nullptr &&
         std::abs(normal->dot(point - tree_.points()[nearest.index])) <= 0.5 * options_.tight_distance;
}

RelocalizationResult Relocalizer::around(const PointCloud& scan, double x, double y, double yaw,
                                         std::optional<double> z) {
  // The keyframe nearest the hint tells the ground there: its height, when the hint has none (the level
  // the robot that made the map drove), and its slope; with a height, the nearest in 3D (a bridge deck
  // over a road: the level the operator picked).
  const Eigen::Isometry3d* nearest = nullptr;
  double nearest_distance = std::numeric_limits<double>::infinity();
  for (const Eigen::Isometry3d& keyframe : map_->keyframe_poses) {
    const Eigen::Vector3d d = keyframe.translation() - Eigen::Vector3d(x, y, z.value_or(0.0));
    const double distance = z ? d.norm() : d.head<2>().norm();
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = &keyframe;
    }
  }
  const Eigen::Vector3d up = nearest != nullptr ? ground_up(*nearest) : Eigen::Vector3d::UnitZ();
  // The candidates stand on that ground's plane, through the hint at its height or through the keyframe.
  const Eigen::Vector3d on_plane =
      z || nearest == nullptr ? Eigen::Vector3d(x, y, z.value_or(0.0)) : nearest->translation();
  const auto height_at = [&](double px, double py) {
    return on_plane.z() - (up.x() * (px - on_plane.x()) + up.y() * (py - on_plane.y())) / up.z();
  };
  std::vector<Eigen::Isometry3d> poses;
  const int steps = static_cast<int>(std::floor(options_.hint_radius / options_.position_step));
  const int turns = static_cast<int>(std::floor(options_.hint_yaw / options_.yaw_step));
  for (int i = -steps; i <= steps; ++i)
    for (int j = -steps; j <= steps; ++j) {
      const double dx = i * options_.position_step;
      const double dy = j * options_.position_step;
      if (std::hypot(dx, dy) > options_.hint_radius + 1e-9)
        continue;
      const Eigen::Vector3d position(x + dx, y + dy, height_at(x + dx, y + dy));
      for (int k = -turns; k <= turns; ++k)
        poses.push_back(pose_on(position, up, yaw + k * options_.yaw_step));
    }
  RelocalizationResult result = search(scan, std::move(poses), true);
  keep_within_hint(result, x, y, yaw);
  return result;
}

void Relocalizer::keep_within_hint(RelocalizationResult& result, double x, double y, double yaw) const {
  // ICP refines a candidate near the edge of the searched area onward: on the campus bridge deck a hint
  // 5 m off was found 3.6 m from it, 1.6 m from the truth, and every later scan's right match was then
  // refused as a jump. What the operator was promised is a search within the radius: a place outside it
  // is neither taken nor followed. The candidates are a grid: one at the edge stands for the half step
  // beyond it too.
  const auto inside = [&](const Eigen::Isometry3d& pose) {
    const double heading = std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
    return std::hypot(pose.translation().x() - x, pose.translation().y() - y) <=
               options_.hint_radius + options_.position_step / 2.0 &&
           std::abs(wrap_angle(heading - yaw)) <= options_.hint_yaw + options_.yaw_step / 2.0;
  };
  std::erase_if(result.places, [&](const Eigen::Isometry3d& place) { return !inside(place); });
  if (!result.refined || inside(result.pose))
    return;
  char text[200];
  std::snprintf(
      text, sizeof text,
      "the best fit, at (%.1f, %.1f), is %.1f m and %.0f degrees from the estimate: outside the "
      "%.0f m and %.0f degrees searched",
      result.pose.translation().x(), result.pose.translation().y(),
      std::hypot(result.pose.translation().x() - x, result.pose.translation().y() - y),
      std::abs(wrap_angle(std::atan2(result.pose.linear()(1, 0), result.pose.linear()(0, 0)) - yaw)) * 180.0 /
          std::numbers::pi,
      options_.hint_radius, options_.hint_yaw * 180.0 / std::numbers::pi);
  result.found = false;
  result.refined = false;  // nothing to follow there
  result.message = text;
}

RelocalizationResult Relocalizer::anywhere(const PointCloud& scan) {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Eigen::Vector3d> places;
  for (const Eigen::Isometry3d& keyframe : map_->keyframe_poses) {
    const Eigen::Vector3d place = keyframe.translation();
    const bool seen = std::ranges::any_of(
        places, [&](const Eigen::Vector3d& p) { return (p - place).norm() < options_.position_step; });
    if (seen)
      continue;
    places.push_back(place);
    const int turns = static_cast<int>(std::lround(2.0 * std::numbers::pi / options_.yaw_step));
    for (int k = 0; k < turns; ++k)
      poses.push_back(pose_on(place, ground_up(keyframe), k * 2.0 * std::numbers::pi / turns));
  }
  return search(scan, std::move(poses), false);
}

RelocalizationResult Relocalizer::search(const PointCloud& scan, std::vector<Eigen::Isometry3d> poses,
                                         bool hinted) {
  const auto start = std::chrono::steady_clock::now();
  RelocalizationResult result;
  result.candidates = poses.size();
  const PointCloud thinned = voxel_downsample(scan, options_.score_voxel);
  if (thinned.empty() || poses.empty()) {
    result.message = poses.empty() ? "the map has no places to search" : "the scan has no points";
    return result;
  }
  PointCloud structure = structure_of(scan);
  // A scan of nothing but ground (open, uneven terrain): near a hint the terrain's shape is all there is
  // to go by; anywhere, too many places have ground like it (measured: docs/benchmarks.md).
  if (structure.size() < options_.min_structure_points) {
    if (!hinted) {
      result.message = "the scan sees nothing but ground, which too many places have: give a hint";
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
    structure = voxel_downsample(scan, options_.structure_voxel);
  }
  std::vector<Candidate> candidates;
  candidates.reserve(poses.size());
  for (const Eigen::Isometry3d& pose : poses)
    candidates.push_back({pose, score(thinned, pose)});
  const std::size_t kept = std::min(options_.refined, candidates.size());
  std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(kept),
                    candidates.end(),
                    [](const Candidate& a, const Candidate& b) { return a.score > b.score; });

  std::vector<Candidate> best;
  for (std::size_t i = 0; i < kept; ++i)
    best.push_back(candidates[i]);
  RelocalizationResult decided = decide(scan, structure, best);
  decided.candidates = result.candidates;
  decided.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return decided;
}

RelocalizationResult Relocalizer::follow(const PointCloud& scan,
                                         const std::vector<Eigen::Isometry3d>& places) {
  const auto start = std::chrono::steady_clock::now();
  PointCloud structure = structure_of(scan);
  const bool bare_ground = structure.size() < options_.min_structure_points;
  if (bare_ground)
    structure = voxel_downsample(scan, options_.structure_voxel);
  std::vector<Candidate> candidates;
  for (const Eigen::Isometry3d& place : places)
    candidates.push_back({place, 0.0});
  RelocalizationResult result = decide(scan, structure, candidates);
  result.candidates = places.size();
  // A scan of nothing but ground drops the places it does not fit and decides nothing: flat ground fits
  // any place that stands on it, and the one left would be whichever the first scans kept (the campus
  // plateau: 4 of 100 followed searches taken there 0.4-3.4 m off, docs/benchmarks.md "Finding the robot").
  if (bare_ground) {
    if (result.found)
      result.places = {result.pose};
    result.found = false;
    if (!result.places.empty())
      result.message = "the scan sees nothing but ground: its places are followed on";
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
  // None of the places fits this scan: they were all wrong (the few the first scan's search refined,
  // metres from the robot in a hallway or on the deck). The whole map is searched with this scan instead,
  // and its places are the ones to follow on.
  if (!result.found && result.places.empty() && !places.empty()) {
    RelocalizationResult anew = anywhere(scan);
    anew.candidates += result.candidates;
    anew.message = "none of the places followed fits; searched the whole map: " + anew.message;
    anew.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return anew;
  }
  // A place is taken only once a scan leaves it where the last one put it: one that this scan's fit moved
  // (along the deck's railings, a hallway) was held there by what the last scan saw, and the next scan
  // tells whether this one's is better (campus tilting, a hint then the next scans: 97 -> 98 % right
  // without the basins in decide, a find 0.39 m along the deck gone; docs/benchmarks.md "Finding the
  // robot").
  if (result.found) {
    const bool settled = std::ranges::any_of(places, [&](const Eigen::Isometry3d& place) {
      const Eigen::Isometry3d d = place.inverse() * result.pose;
      return d.translation().norm() <= options_.settled_metres &&
             Eigen::AngleAxisd(d.linear()).angle() <= options_.settled_radians;
    });
    if (!settled) {
      result.found = false;
      result.places = {result.pose};
      result.message = "the place moved as this scan fitted it: it is followed on until a scan leaves it";
    }
  }
  // The places followed are the few the first scan's search refined: the right one may not be among
  // them, and the next scans then choose between wrong ones. A place is taken only if a search around it
  // with this scan agrees (campus: wrong finds 12 -> 7 %, docs/benchmarks.md "Finding the robot").
  if (result.found) {
    const Eigen::Isometry3d found = result.pose;
    const auto same = [&](const Eigen::Isometry3d& other) {
      const Eigen::Isometry3d d = found.inverse() * other;
      return d.translation().norm() <= options_.distinct_metres &&
             Eigen::AngleAxisd(d.linear()).angle() <= options_.distinct_radians;
    };
    const RelocalizationResult check = around(scan, found.translation().x(), found.translation().y(),
                                              heading_of(found), found.translation().z());
    const bool agrees = check.found ? same(check.pose) : std::ranges::any_of(check.places, same);
    result.candidates += check.candidates;
    if (!agrees) {
      result.found = false;
      // The better place near it (found, or those that fit as well) is the one to follow on.
      result.places = check.found ? std::vector<Eigen::Isometry3d>{check.pose} : check.places;
      result.message = "the place followed fits worse than another near it: " + check.message;
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

RelocalizationResult Relocalizer::decide(const PointCloud& scan, const PointCloud& structure,
                                         const std::vector<Candidate>& candidates) {
  struct Refined {
    Eigen::Isometry3d pose;
    double share = 0.0;
    double rmse = 0.0;
    double structure = 0.0;
    double covered_structure = 0.0;
  };
  RelocalizationResult result;
  std::vector<Refined> refined;
  const auto refine = [&](const Eigen::Isometry3d& start) {
    const RegistrationResult fit = registration_.register_scan(scan, start);
    if (!fit.refined.matrix().allFinite() || fit.source_points == 0)
      return;
    const StructureFit structure_at = structure_fit(structure, fit.refined);
    refined.push_back({fit.refined, static_cast<double>(fit.pairs) / static_cast<double>(fit.source_points),
                       fit.rmse, structure_at.share, structure_at.covered_share});
  };
  for (const Candidate& candidate : candidates)
    refine(candidate.pose);
  if (refined.empty()) {
    result.message = "no candidate could be registered";
    return result;
  }
  const auto fits = [&](const Refined& r) {
    return r.share >= options_.min_inlier_share && r.rmse <= options_.max_rmse &&
           r.structure >= options_.min_structure_share &&
           r.covered_structure >= options_.min_covered_structure_share;
  };
  // A place about to be taken is refined again from starts basin_step to each side of it: on open ground
  // with few objects a scan settles in basins 0.2 m apart, and the candidates refined may all have come
  // from one of them (the campus plateau's lidar scans, docs/benchmarks.md "Finding the robot"). A better
  // basin so found is taken; one elsewhere that fits as well makes the place ambiguous (below).
  auto best = std::ranges::max_element(refined, {}, &Refined::structure);
  if (options_.basin_step > 0.0 && fits(*best)) {
    const Eigen::Isometry3d around_it = best->pose;
    const double s = options_.basin_step;
    for (const Eigen::Vector3d& side : {Eigen::Vector3d(s, 0, 0), Eigen::Vector3d(-s, 0, 0),
                                        Eigen::Vector3d(0, s, 0), Eigen::Vector3d(0, -s, 0)})
      refine(around_it * Eigen::Translation3d(side));
    best = std::ranges::max_element(refined, {}, &Refined::structure);
  }
  result.refined = true;
  result.pose = best->pose;
  result.inlier_share = best->share;
  result.rmse = best->rmse;
  result.structure_share = best->structure;
  result.covered_structure_share = best->covered_structure;

  const Refined* rival = nullptr;
  result.places.push_back(best->pose);
  for (const Refined& other : refined) {
    const Eigen::Isometry3d apart = best->pose.inverse() * other.pose;
    const bool elsewhere = apart.translation().norm() > options_.distinct_metres ||
                           Eigen::AngleAxisd(apart.linear()).angle() > options_.distinct_radians;
    const bool as_well = other.structure >= best->structure - options_.ambiguity_margin &&
                         other.share >= options_.min_inlier_share;
    if (!as_well)
      continue;
    // The places that fit as well, one per place: what the next scans decide between.
    const bool known = std::ranges::any_of(result.places, [&](const Eigen::Isometry3d& place) {
      const Eigen::Isometry3d d = place.inverse() * other.pose;
      return d.translation().norm() <= options_.distinct_metres &&
             Eigen::AngleAxisd(d.linear()).angle() <= options_.distinct_radians;
    });
    if (!known)
      result.places.push_back(other.pose);
    if (elsewhere && rival == nullptr)
      rival = &other;
  }
  if (rival != nullptr) {
    char text[192];
    std::snprintf(text, sizeof(text),
                  "two places fit as well (%.0f %% and %.0f %% of the scan's walls and objects, %.1f m "
                  "apart): give a hint nearer the robot",
                  100.0 * best->structure, 100.0 * rival->structure,
                  (best->pose.translation() - rival->pose.translation()).norm());
    result.message = text;
    return result;
  }
  result.places.clear();
  if (best->share < options_.min_inlier_share || best->rmse > options_.max_rmse ||
      best->structure < options_.min_structure_share) {
    char text[192];
    std::snprintf(text, sizeof(text),
                  "no place fits: at best %.0f %% of the scan on the map (RMSE %.2f m), %.0f %% of its walls "
                  "and objects within %.0f cm; %.0f %% and %.0f %% needed",
                  100.0 * best->share, best->rmse, 100.0 * best->structure, 100.0 * options_.tight_distance,
                  100.0 * options_.min_inlier_share, 100.0 * options_.min_structure_share);
    result.message = text;
    return result;
  }
  if (best->covered_structure < options_.min_covered_structure_share) {
    char text[192];
    std::snprintf(text, sizeof(text),
                  "no place fits closely: at best %.0f %% of the walls and objects the map has there within "
                  "%.0f cm; %.0f %% needed",
                  100.0 * best->covered_structure, 100.0 * options_.tight_distance,
                  100.0 * options_.min_covered_structure_share);
    result.message = text;
    return result;
  }
  result.found = true;
  const Eigen::Vector3d t = best->pose.translation();
  char text[192];
  std::snprintf(text, sizeof(text),
                "found at x %.2f, y %.2f, heading %.0f degrees (%.0f %% of the scan on the map, %.0f %% of "
                "its walls and objects within %.0f cm)",
                t.x(), t.y(), heading_of(best->pose) * 180.0 / std::numbers::pi, 100.0 * best->share,
                100.0 * best->structure, 100.0 * options_.tight_distance);
  result.message = text;
  return result;
}

}  // namespace strata

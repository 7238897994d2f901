// strata_relocalization_bench [world] [seconds] [samples] [tilting|lidar]: finding the robot in a saved
// map (issue 22). A map is made as the server makes it (the pose graph over one simulated run, seed 1, the
// stop-and-go scanner or the spinning lidar; its keyframes as a saved map keeps them), then scans of
// another run (seed 2) at random places of it are looked for: around a hint within 2 m and 30 degrees of
// the truth, and with no hint at all. A find counts as right within 0.2 m and 2 degrees of the truth as
// the map has it (below). Prints JSON. STRATA_BENCH_VERBOSE=1 says how each sample went on stderr;
// STRATA_BENCH_ONLY=N runs sample N alone (0-based, the same as in the full run) and says how each
// followed scan went.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/localization/graph_localizer.hpp"
#include "core/localization/localization_map.hpp"
#include "core/localization/relocalizer.hpp"
#include "core/localization/scan_to_map_localizer.hpp"
#include "core/points/deskew.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/app/memory_policy.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

using namespace strata;

namespace {

struct Seen {
  PointCloud points;
  Eigen::Isometry3d truth;
  bool in_hallway = false;  ///< under a world box named "...hallway-ceiling" (the campus's featureless one)
  Eigen::Isometry3d odometry = Eigen::Isometry3d::Identity();  ///< the base in the odometry frame
};

bool right(const RelocalizationResult& result, const Eigen::Isometry3d& truth) {
  const double heading =
      std::abs(std::remainder(heading_of(result.pose) - heading_of(truth), 2.0 * std::numbers::pi));
  return (result.pose.translation() - truth.translation()).norm() <= 0.2 &&
         heading <= 2.0 * std::numbers::pi / 180.0;
}

struct Tally {
  std::size_t right = 0, wrong = 0, refused = 0;
  std::vector<double> seconds;
  void add(const RelocalizationResult& result, const Eigen::Isometry3d& truth) {
    seconds.push_back(result.seconds);
    if (!result.found)
      ++refused;
    else if (::right(result, truth))
      ++right;
    else
      ++wrong;
  }
  [[nodiscard]] std::string json() const {
    std::vector<double> sorted = seconds;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
    const double worst = sorted.empty() ? 0.0 : sorted.back();
    const double n = static_cast<double>(seconds.size());
    char text[256];
    std::snprintf(
        text, sizeof(text),
        "{\"right\": %zu, \"wrong\": %zu, \"refused\": %zu, \"right_share\": %.3f, \"wrong_share\": %.3f, "
        "\"median_s\": %.3f, \"max_s\": %.3f}",
        right, wrong, refused, n > 0 ? static_cast<double>(right) / n : 0.0,
        n > 0 ? static_cast<double>(wrong) / n : 0.0, median, worst);
    return text;
  }
};

}  // namespace

int main(int argc, char** argv) {
  strata::app::keep_freed_memory();  // as the server does: the scan path's buffers stay mapped
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double duration = argc > 2 ? std::atof(argv[2]) : (world_name == "yard" ? 200.0 : 800.0);
  const std::size_t samples = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 50;
  const std::string scanner = argc > 4 ? argv[4] : "tilting";
  const bool lidar = scanner == "lidar";
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));
  RelocalizationOptions relocalization;  // followed and re-searched as the server does (follow_metres, ...)
  const auto run_config = [&](std::uint64_t seed) {
    sim::SimulatorConfig config;
    config.seed = seed;
    config.scanner = lidar ? sim::ScannerKind::kLidar : sim::ScannerKind::kTilting;
    return config;
  };
  // A lidar's revolution, deskewed by the odometry's motion since the last one, as the server does.
  std::optional<std::pair<double, Pose2>> last_odometry;
  const auto scan_points = [&](const ScanEvent& scan) {
    std::vector<float> times;
    PointCloud points = pipeline::points_in_base(scan, 0.3, &times);
    const Pose2 odometry{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw};
    if (lidar && last_odometry && scan.stamp > last_odometry->first &&
        scan.stamp - last_odometry->first < 1.0) {
      const double dt = scan.stamp - last_odometry->first;
      const Pose2 moved = odometry.relative_to(last_odometry->second);
      deskew(points, times, Pose2{moved.x / dt, moved.y / dt, moved.theta / dt});
    }
    last_odometry = {scan.stamp, odometry};
    return points;
  };

  // The map: one run through the pose graph, as the server saves it.
  const auto map_start = std::chrono::steady_clock::now();
  sim::Simulator mapping_run(world, run_config(1));
  GraphLocalizer localizer(
      {}, mapping_run.sample().truth->to_isometry() * mapping_run.sample().odometry.to_isometry().inverse());
  std::map<double, Eigen::Isometry3d> mapping_truth;  // by scan stamp
  for (double t = 0.0; t < duration; t += 0.01) {
    mapping_run.step(0.01);
    for (const ScanEvent& scan : mapping_run.take_scans()) {
      mapping_truth[scan.stamp] = scan.truth->to_isometry();
      static_cast<void>(localizer.add_scan(
          scan_points(scan), Pose2{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw},
          scan.stamp, scan.sensor_to_base.translation(), scan.gravity));
      localizer.close_loops();
    }
  }
  const std::vector<KeyframePose> keyframes = localizer.keyframes();
  auto map = std::make_shared<const LocalizationMap>(make_localization_map(keyframes));
  // The map is where the mapping run's estimate put things, up to its own error: the right answer for a
  // scan is its true pose carried into the map by the nearest keyframe's error (its map pose against its
  // truth), not the truth itself.
  struct Offset {
    Eigen::Vector3d truth_place;
    Eigen::Isometry3d map_from_truth;
  };
  std::vector<Offset> offsets;
  double worst_map_error = 0.0;
  for (const KeyframePose& k : keyframes) {
    const Eigen::Isometry3d& truth = mapping_truth.at(k.keyframe->stamp);
    offsets.push_back({truth.translation(), k.pose * truth.inverse()});
    worst_map_error = std::max(worst_map_error, (k.pose.translation() - truth.translation()).norm());
  }
  const auto in_map = [&](const Eigen::Isometry3d& truth) {
    const auto nearest = std::ranges::min_element(
        offsets, {}, [&](const Offset& o) { return (o.truth_place - truth.translation()).squaredNorm(); });
    return nearest->map_from_truth * truth;
  };
  const double map_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - map_start).count();

  // The thesis's featureless hallway (campus) is the same for metres along itself: its samples are also
  // counted apart, to tell that limit from the rest.
  const auto in_hallway = [&](const Eigen::Vector3d& p) {
    return std::ranges::any_of(world->description().boxes, [&](const sim::BoxShape& box) {
      return box.name.ends_with("hallway-ceiling") && std::abs(p.x() - box.center.x()) <= box.size.x() / 2 &&
             std::abs(p.y() - box.center.y()) <= box.size.y() / 2;
    });
  };
  // The scans to find: another run's.
  std::vector<Seen> seen;
  double reference_shift = 0.0;
  std::size_t references_kept = 0;
  sim::Simulator other_run(world, run_config(2));
  last_odometry.reset();
  // A lidar's every 10th revolution (a second apart, as the 5 next scans followed are a stop-and-go
  // scanner's few metres): ten times as many would not fit in memory.
  const std::size_t every = lidar ? 10 : 1;
  std::size_t revolutions = 0;
  // The samples are scans of the run's first `duration` seconds; the run goes on until the robot has
  // driven follow_metres more, so that the last of them can be followed as a robot that drives on is.
  std::size_t sampled = 0;  // scans to sample from: seen[0, sampled)
  double driven_after = 0.0;
  std::optional<Eigen::Vector3d> last_position;
  for (double t = 0.0; t < duration || driven_after < relocalization.follow_metres; t += 0.01) {
    other_run.step(0.01);
    const Eigen::Vector3d position = other_run.sample().odometry.position;
    if (t >= duration && last_position)
      driven_after += (position - *last_position).head<2>().norm();
    last_position = position;
    for (const ScanEvent& scan : other_run.take_scans()) {
      PointCloud points = scan_points(scan);
      if (revolutions++ % every == 0) {
        seen.push_back({std::move(points), in_map(scan.truth->to_isometry()),
                        in_hallway(scan.truth->position), scan.odometry.to_isometry()});
        if (scan.stamp < duration)
          sampled = seen.size();
      }
    }
  }

  // Where tracking from that pose settles: the map is only locally consistent (its keyframes are up to
  // worst_keyframe_error_m off the truth), and a keyframe's error carried a few metres is off by a
  // few centimetres per degree. ICP from the carried truth against the map gives the pose the map itself
  // says; it is the reference unless it slid more than 0.5 m (then the carried truth is kept).
  {
    RegistrationOptions options = LocalizerOptions::default_registration();
    options.limits.max_translation_jump = std::numeric_limits<double>::infinity();
    options.limits.max_rotation_jump = std::numeric_limits<double>::infinity();
    ScanRegistration tracking(options);
    tracking.set_thinned_target(map->cloud());
    double moved_sum = 0.0;
    std::size_t kept = 0;
    for (Seen& s : seen) {
      const RegistrationResult fit = tracking.register_scan(s.points, s.truth);
      const double moved = (fit.refined.translation() - s.truth.translation()).norm();
      if (fit.refined.matrix().allFinite() && moved < 0.5) {
        moved_sum += moved;
        s.truth = fit.refined;
      } else {
        ++kept;
      }
    }
    reference_shift = seen.empty() ? 0.0 : moved_sum / static_cast<double>(seen.size());
    references_kept = kept;
  }

  if (const char* refined = std::getenv("STRATA_BENCH_REFINED"))  // candidates refined by ICP per search
    relocalization.refined = std::strtoul(refined, nullptr, 10);
  if (const char* step = std::getenv("STRATA_BENCH_BASIN_STEP"))  // a find's basin check, m (0: none)
    relocalization.basin_step = std::atof(step);
  Relocalizer relocalizer(map, relocalization);
  std::optional<std::size_t> only;
  if (const char* one = std::getenv("STRATA_BENCH_ONLY"))
    only = std::strtoul(one, nullptr, 10);
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, sampled - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally hinted, blind, hinted_outside, blind_outside, followed, followed_outside, blind_followed,
      blind_followed_outside;
  std::vector<double> follow_scans;  // scans followed until a followed search decided
  // A search that found places fitting as well follows them through the run's next scans, each moved by
  // the odometry since, until one place is left (as the server does while the robot drives on). A lost
  // robot (no hint) that has no places to follow is looked for in the whole map again, at once after a
  // follow ended and every lost_search_every scans after a search (as the server does).
  const auto follow = [&](std::size_t index, RelocalizationResult result, bool lost) {
    // A hint's search that found nothing fitting follows its best candidate (as the server does); a lost
    // robot's searches the whole map again instead.
    std::vector<Eigen::Isometry3d> places = lost ? result.places : result.places_to_follow();
    std::size_t j = index;
    double driven = 0.0;
    std::size_t wait = relocalization.lost_search_every - 1;  // scans until the next whole-map search
    while (!result.found && (lost || !places.empty()) && j + 1 < seen.size() &&
           driven < relocalization.follow_metres) {
      ++j;
      const Eigen::Isometry3d moved = seen[j - 1].odometry.inverse() * seen[j].odometry;
      driven += moved.translation().head<2>().norm();
      if (!places.empty()) {
        for (Eigen::Isometry3d& place : places)
          place = place * moved;
        result = relocalizer.follow(seen[j].points, places);
        wait = 0;
      } else if (wait > 0) {
        --wait;
        continue;
      } else {
        result = relocalizer.anywhere(seen[j].points);
        wait = relocalization.lost_search_every - 1;
      }
      places = result.places;
      if (std::getenv("STRATA_BENCH_VERBOSE") != nullptr && only) {
        std::fprintf(stderr, "  scan %zu (%.1f m driven): %s; places, m from the truth:", j - index, driven,
                     result.message.c_str());
        for (const Eigen::Isometry3d& place : places)
          std::fprintf(stderr, " %.2f", (place.translation() - seen[j].truth.translation()).norm());
        std::fprintf(stderr, "\n");
      }
    }
    follow_scans.push_back(static_cast<double>(j - index));
    return std::pair{result, j};
  };
  double candidates_blind = 0.0;
  for (std::size_t n = 0; n < samples; ++n) {
    const std::size_t index = pick(random);
    const Seen& s = seen[index];
    // A hint anywhere within 2 m and 30 degrees of the truth.
    const double radius = 2.0 * std::sqrt(unit(random));
    const double angle = 2.0 * std::numbers::pi * unit(random);
    const double turn = (2.0 * unit(random) - 1.0) * std::numbers::pi / 6.0;
    if (only && *only != n)  // STRATA_BENCH_ONLY: one sample, to look at it (its draws made all the same)
      continue;
    const RelocalizationResult around =
        relocalizer.around(s.points, s.truth.translation().x() + radius * std::cos(angle),
                           s.truth.translation().y() + radius * std::sin(angle), heading_of(s.truth) + turn);
    hinted.add(around, s.truth);
    if (!s.in_hallway)
      hinted_outside.add(around, s.truth);
    const auto [after, at] = follow(index, around, false);
    if (std::getenv("STRATA_BENCH_VERBOSE") != nullptr && at != index) {
      std::fprintf(stderr, "places at the start, m from the truth:");
      for (const Eigen::Isometry3d& place : around.places)
        std::fprintf(stderr, " %.2f", (place.translation() - s.truth.translation()).norm());
      std::fprintf(stderr, "\n");
    }
    followed.add(after, seen[at].truth);
    if (!s.in_hallway)
      followed_outside.add(after, seen[at].truth);
    if (std::getenv("STRATA_BENCH_VERBOSE") != nullptr && at != index)
      std::fprintf(stderr, "followed %zu scans: %s %s (%.2f m off)\n", at - index,
                   !after.found                   ? "refused"
                   : right(after, seen[at].truth) ? "right"
                                                  : "wrong",
                   after.message.c_str(), (after.pose.translation() - seen[at].truth.translation()).norm());
    const RelocalizationResult anywhere = relocalizer.anywhere(s.points);
    candidates_blind = static_cast<double>(anywhere.candidates);
    if (std::getenv("STRATA_BENCH_VERBOSE") != nullptr) {
      for (const auto& [what, result] : {std::pair{"hint", &around}, std::pair{"no hint", &anywhere}}) {
        std::fprintf(stderr, "%s %s, at %.1f %.1f: %s (%.2f m off)\n",
                     !result->found            ? "refused"
                     : right(*result, s.truth) ? "right"
                                               : "wrong",
                     what, s.truth.translation().x(), s.truth.translation().y(), result->message.c_str(),
                     (result->pose.translation() - s.truth.translation()).norm());
      }
    }
    blind.add(anywhere, s.truth);
    if (!s.in_hallway)
      blind_outside.add(anywhere, s.truth);
    const auto [blind_after, blind_at] = follow(index, anywhere, true);
    blind_followed.add(blind_after, seen[blind_at].truth);
    if (!s.in_hallway)
      blind_followed_outside.add(blind_after, seen[blind_at].truth);
  }
  std::printf(
      "{\"world\": \"%s\", \"scanner\": \"%s\", \"seconds\": %.0f, \"samples\": %zu, \"map\": "
      "{\"keyframes\": %zu, \"points\": "
      "%zu, "
      "\"made_s\": %.1f, \"worst_keyframe_error_m\": %.2f, \"mean_reference_shift_m\": %.3f, "
      "\"carried_truth_kept\": %zu}, \"hint_within_2m_30deg\": %s, \"no_hint\": %s, "
      "\"no_hint_candidates\": %.0f, \"hint_then_next_scans\": %s, \"no_hint_then_next_scans\": %s, "
      "\"outside_featureless_hallway\": {\"hint_within_2m_30deg\": %s, \"no_hint\": %s, "
      "\"hint_then_next_scans\": %s, \"no_hint_then_next_scans\": %s}}\n",
      world_name.c_str(), scanner.c_str(), duration, samples, map->keyframe_poses.size(), map->points.size(),
      map_seconds, worst_map_error, reference_shift, references_kept, hinted.json().c_str(),
      blind.json().c_str(), candidates_blind, followed.json().c_str(), blind_followed.json().c_str(),
      hinted_outside.json().c_str(), blind_outside.json().c_str(), followed_outside.json().c_str(),
      blind_followed_outside.json().c_str());
  return 0;
}

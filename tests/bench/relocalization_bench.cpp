// strata_relocalization_bench [world] [seconds] [samples]: finding the robot in a saved map (issue 22).
// A map is made as the server makes it (the pose graph over one simulated run, seed 1, the stop-and-go
// scanner; its keyframes as a saved map keeps them), then scans of another run (seed 2) at random places
// of it are looked for: around a hint within 2 m and 30 degrees of the truth, and with no hint at all.
// A find counts as right within 0.2 m and 2 degrees of the truth. Prints JSON.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/localization/graph_localizer.hpp"
#include "core/localization/localization_map.hpp"
#include "core/localization/relocalizer.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"

using namespace strata;

namespace {

struct Seen {
  PointCloud points;
  Eigen::Isometry3d truth;
};

double yaw_of(const Eigen::Isometry3d& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

bool right(const RelocalizationResult& result, const Eigen::Isometry3d& truth) {
  const double heading =
      std::abs(std::remainder(yaw_of(result.pose) - yaw_of(truth), 2.0 * std::numbers::pi));
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
  const std::string world_name = argc > 1 ? argv[1] : "campus";
  const double duration = argc > 2 ? std::atof(argv[2]) : (world_name == "yard" ? 200.0 : 800.0);
  const std::size_t samples = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 50;
  const auto world = std::make_shared<const sim::World>(sim::builtin_world(world_name));

  // The map: one run through the pose graph, as the server saves it.
  const auto map_start = std::chrono::steady_clock::now();
  sim::Simulator mapping_run(world, {.seed = 1});
  GraphLocalizer localizer(
      {}, mapping_run.sample().truth->to_isometry() * mapping_run.sample().odometry.to_isometry().inverse());
  std::map<double, Eigen::Isometry3d> mapping_truth;  // by scan stamp
  for (double t = 0.0; t < duration; t += 0.01) {
    mapping_run.step(0.01);
    for (const ScanEvent& scan : mapping_run.take_scans()) {
      mapping_truth[scan.stamp] = scan.truth->to_isometry();
      static_cast<void>(
          localizer.add_scan(pipeline::points_in_base(scan),
                             Pose2{scan.odometry.position.x(), scan.odometry.position.y(), scan.odometry.yaw},
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

  // The scans to find: another run's.
  std::vector<Seen> seen;
  sim::Simulator other_run(world, {.seed = 2});
  for (double t = 0.0; t < duration; t += 0.01) {
    other_run.step(0.01);
    for (const ScanEvent& scan : other_run.take_scans())
      seen.push_back({pipeline::points_in_base(scan), in_map(scan.truth->to_isometry())});
  }

  Relocalizer relocalizer(map);
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, seen.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally hinted, blind;
  double candidates_blind = 0.0;
  for (std::size_t n = 0; n < samples; ++n) {
    const Seen& s = seen[pick(random)];
    // A hint anywhere within 2 m and 30 degrees of the truth.
    const double radius = 2.0 * std::sqrt(unit(random));
    const double angle = 2.0 * std::numbers::pi * unit(random);
    const double turn = (2.0 * unit(random) - 1.0) * std::numbers::pi / 6.0;
    const RelocalizationResult around =
        relocalizer.around(s.points, s.truth.translation().x() + radius * std::cos(angle),
                           s.truth.translation().y() + radius * std::sin(angle), yaw_of(s.truth) + turn);
    hinted.add(around, s.truth);
    const RelocalizationResult anywhere = relocalizer.anywhere(s.points);
    candidates_blind = static_cast<double>(anywhere.candidates);
    if (std::getenv("STRATA_BENCH_VERBOSE") != nullptr) {
      for (const auto& [what, result] : {std::pair{"hint", &around}, std::pair{"no hint", &anywhere}}) {
        if (!result->found || !right(*result, s.truth))
          std::fprintf(stderr, "%s, at %.1f %.1f: %s (%.2f m off)\n", what, s.truth.translation().x(),
                       s.truth.translation().y(), result->message.c_str(),
                       (result->pose.translation() - s.truth.translation()).norm());
      }
    }
    blind.add(anywhere, s.truth);
  }
  std::printf(
      "{\"world\": \"%s\", \"seconds\": %.0f, \"samples\": %zu, \"map\": {\"keyframes\": %zu, \"points\": "
      "%zu, "
      "\"made_s\": %.1f, \"worst_keyframe_error_m\": %.2f}, \"hint_within_2m_30deg\": %s, \"no_hint\": %s, "
      "\"no_hint_candidates\": %.0f}\n",
      world_name.c_str(), duration, samples, map->keyframe_poses.size(), map->points.size(), map_seconds,
      worst_map_error, hinted.json().c_str(), blind.json().c_str(), candidates_blind);
  return 0;
}

// strata_goal_drive_bench: are goals on seen ground reached? (issue 21) Starts the real `strata serve` with
// the simulated robot and lets it drive its world's demo route for a while. Then, goal after goal, as an
// operator would: downloads the live map over REST, picks a place 2-20 m from the robot that a survey of the
// world says it can reach with room to spare and that the live map has measured at that height
// (tests/support/seen_goals.hpp), sends it with POST /api/v1/goal and follows GET /api/v1/goal until the
// goal is reached, fails or times out; the next goal starts where the robot then stands. Not a test: it
// prints one line per goal and a summary, "key=value" separated by spaces.
//
//   strata_goal_drive_bench [--world yard|campus] [--scanner tilting|lidar] [--warmup S] [--goals N]
//                           [--timeout S] [--time-scale X] [--seed K] [--dump DIR] [--record DIR]
//                           [--goals-at X,Y,Z;X,Y,Z...] [--imu-calibration FILE]
//   defaults: yard, tilting, 60 simulated seconds of demo route, 20 goals, 240 simulated seconds per goal,
//   time scale 20, seed 1 (picks the goals; the simulator's own seed is the server's default); with --dump,
//   the map downloaded before each goal that was not reached is saved as DIR/goal_<i>.strata, and the one
//   downloaded when it ended, where the robot stands, as DIR/goal_<i>_end.strata; with
//   --record, the server records its scans and odometry there (`strata serve --replay` plays them again);
//   with --goals-at, the goals are these places (true coordinates) in turn instead of random seen ground,
//   e.g. up and down the campus bridge ramp: --goals-at "84,-28.75,3;44,-28.75,0" (issue 58); with
//   --imu-calibration, the server keeps what it learns of its IMU's mounting there and starts from it (as a
//   robot does from its second run on; without it, every run starts unknowing)
//
//   goal     i, where from and to, distance; phase it ended in (reached, failed, timeout) and the reason;
//            accepted: the server planned a way and drove (it did not refuse the goal); simulated seconds;
//            error_m: the robot's true distance from the goal at the end; pose_xy_m, pose_z_m: the
//            estimate's error when the goal was sent (the goal is in true coordinates, the map in the
//            estimate's)
//   summary  goals tried, accepted and reached, and their shares; the scans the localizer processed and
//            dropped (busy); failures by reason
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/mls/mls_config.hpp"
#include "core/mls/mls_file.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "integration/clients.hpp"
#include "integration/server_process.hpp"
#include "server/pipeline/navigator.hpp"
#include "tests/support/seen_goals.hpp"

namespace {

using namespace strata;
namespace http = boost::beast::http;
using testing::http_request;
using testing::kTestOperatorToken;

struct Options {
  std::string world = "yard";
  std::string scanner = "tilting";
  double warmup = 60.0;
  int goals = 20;
  double timeout = 240.0;
  std::string time_scale = "20";
  unsigned seed = 1;
  std::string dump;             ///< a folder for the maps of goals not reached; empty: none saved
  std::string record;           ///< a folder the server records the run into; empty: not recorded
  std::string imu_calibration;  ///< the server's IMU calibration file (kept between runs); empty: a fresh one
  std::vector<Eigen::Vector3d> goals_at;  ///< fixed goals, taken in turn; empty: random seen ground
};

/// "X,Y,Z;X,Y,Z..." as places; throws on anything else, so a typo never runs as random goals.
std::vector<Eigen::Vector3d> parse_places(const std::string& text) {
  std::vector<Eigen::Vector3d> places;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find(';', start), text.size());
    Eigen::Vector3d place;
    int used = 0;
    const std::string item = text.substr(start, end - start);
    if (std::sscanf(item.c_str(), "%lf,%lf,%lf%n", &place.x(), &place.y(), &place.z(), &used) != 3 ||
        used != static_cast<int>(item.size()))
      throw std::invalid_argument("--goals-at: \"" + item + "\" is not X,Y,Z");
    places.push_back(place);
    start = end + 1;
  }
  return places;
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--world")
      options.world = value;
    else if (key == "--scanner")
      options.scanner = value;
    else if (key == "--warmup")
      options.warmup = std::atof(value);
    else if (key == "--goals")
      options.goals = std::atoi(value);
    else if (key == "--timeout")
      options.timeout = std::atof(value);
    else if (key == "--time-scale")
      options.time_scale = value;
    else if (key == "--seed")
      options.seed = static_cast<unsigned>(std::atoi(value));
    else if (key == "--dump")
      options.dump = value;
    else if (key == "--record")
      options.record = value;
    else if (key == "--imu-calibration")
      options.imu_calibration = value;
    else if (key == "--goals-at")
      options.goals_at = parse_places(value);
  }
  return options;
}

/// The navigator's planner graph configuration and the server's map resolution (defaults).
const PatchGraphConfig kNavigatorGraph = pipeline::NavigatorConfig{}.graph;
const double kMapResolution = MlsConfig{}.resolution;

nlohmann::json get_json(std::uint16_t port, const std::string& target) {
  const auto response = http_request(port, http::verb::get, target, {}, kTestOperatorToken);
  if (response.result_int() != 200)
    throw std::runtime_error(target + ": HTTP " + std::to_string(response.result_int()) + " " +
                             response.body());
  return nlohmann::json::parse(response.body());
}

Eigen::Vector3d truth_of(const nlohmann::json& pose) {
  const nlohmann::json& truth = pose.at("truth");
  return {truth.at("x").get<double>(), truth.at("y").get<double>(), truth.at("z").get<double>()};
}

/// The live map as a user downloads it (the file's bytes), and its planner graph as the navigator builds it.
/// The server's map as Download "strata" gives it.
std::string download_map(std::uint16_t port) {
  const auto response =
      http_request(port, http::verb::get, "/api/v1/map?format=strata", {}, kTestOperatorToken);
  if (response.result_int() != 200)
    throw std::runtime_error("map download: HTTP " + std::to_string(response.result_int()));
  return response.body();
}

PatchGraph download_graph(std::uint16_t port, std::string& file) {
  file = download_map(port);
  const MlsMap map = deserialize_mls_map(file, "the downloaded map");
  return PatchGraph(std::make_shared<const SurfaceGrid>(map, CellRegion::of_tiles(map.tile_indices()),
                                                        kNavigatorGraph.traversability),
                    map.resolution(), kNavigatorGraph);
}

struct Outcome {
  std::string phase;  ///< reached, failed, cancelled or timeout
  std::string reason;
  std::string message;    ///< the server's words for a failure
  bool accepted = false;  ///< seen driving, or ended in a phase only driving leads to
  double seconds = 0.0;   ///< simulated
};

Outcome drive_to(std::uint16_t port, const Eigen::Vector3d& goal, double timeout) {
  const nlohmann::json body{{"x", goal.x()}, {"y", goal.y()}, {"z", goal.z()}};
  const auto posted = http_request(port, http::verb::post, "/api/v1/goal", body.dump(), kTestOperatorToken);
  if (posted.result_int() != 202)
    return {.phase = "refused", .reason = "http_" + std::to_string(posted.result_int())};
  const int id = nlohmann::json::parse(posted.body()).at("id").get<int>();
  const double start = get_json(port, "/api/v1/pose").at("stamp").get<double>();
  Outcome outcome;
  while (true) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const nlohmann::json state = get_json(port, "/api/v1/goal");
    const double now = get_json(port, "/api/v1/pose").at("stamp").get<double>();
    outcome.seconds = now - start;
    if (state.at("id").get<int>() != id)
      return {.phase = "replaced"};
    const std::string phase = state.at("phase").get<std::string>();
    if (phase == "driving")
      outcome.accepted = true;
    if (phase == "reached" || phase == "failed" || phase == "cancelled") {
      outcome.phase = phase;
      outcome.reason = state.value("reason", "");
      outcome.message = state.value("message", "");
      // Failures that only come after a plan: the robot was driving.
      outcome.accepted =
          outcome.accepted || phase == "reached" || outcome.reason == "blocked" || outcome.reason == "stuck";
      return outcome;
    }
    if (outcome.seconds > timeout) {
      http_request(port, http::verb::delete_, "/api/v1/goal", {}, kTestOperatorToken);
      outcome.phase = "timeout";
      return outcome;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  if (!options.dump.empty())
    std::filesystem::create_directories(options.dump);  // a map not written is a failure not looked at
  const sim::World world(sim::builtin_world(options.world));
  std::vector<std::string> args{"--world",       options.world,  "--scanner",
                                options.scanner, "--time-scale", options.time_scale};
  if (!options.record.empty())
    args.insert(args.end(), {"--record", options.record});
  if (!options.imu_calibration.empty())
    args.insert(args.end(), {"--imu-calibration", options.imu_calibration});
  testing::ServerProcess server(args);
  const std::uint16_t port = server.port();
  // Surveyed while the robot warms up: surveying takes seconds in which the demo route drives on, so done
  // between reading where the robot is and sending it a goal, it made goals 10 m off their distance.
  std::optional<PatchGraph> truth;
  if (options.goals_at.empty())
    truth = test::surveyed_graph(world, kMapResolution, kNavigatorGraph);
  while (get_json(port, "/api/v1/pose").value("stamp", 0.0) < options.warmup)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));

  std::mt19937 random(options.seed);
  int tried = 0;
  int accepted = 0;
  int reached = 0;
  std::map<std::string, int> failed;
  for (int i = 0; i < options.goals; ++i) {
    const nlohmann::json pose = get_json(port, "/api/v1/pose");
    const Eigen::Vector3d robot = truth_of(pose);
    const Eigen::Vector3d estimate(pose.at("x").get<double>(), pose.at("y").get<double>(),
                                   pose.at("z").get<double>());
    std::string map_file;
    const PatchGraph seen = download_graph(port, map_file);
    std::vector<Eigen::Vector3d> spots;
    if (!options.goals_at.empty()) {
      spots.push_back(options.goals_at[static_cast<std::size_t>(i) % options.goals_at.size()]);
    } else {
      for (const Eigen::Vector3d& spot : test::seen_goal_spots(*truth, seen, robot)) {
        const double distance = std::hypot(spot.x() - robot.x(), spot.y() - robot.y());
        if (distance >= 2.0 && distance <= 20.0)
          spots.push_back(spot);
      }
    }
    if (spots.empty()) {
      std::printf("goal i=%d from=%.2f,%.2f,%.2f none: no seen ground 2-20 m away\n", i, robot.x(), robot.y(),
                  robot.z());
      break;
    }
    const Eigen::Vector3d goal =
        spots[std::uniform_int_distribution<std::size_t>(0, spots.size() - 1)(random)];
    const Outcome outcome = drive_to(port, goal, options.timeout);
    const Eigen::Vector3d end = truth_of(get_json(port, "/api/v1/pose"));
    ++tried;
    accepted += outcome.accepted ? 1 : 0;
    reached += outcome.phase == "reached" ? 1 : 0;
    if (outcome.phase != "reached") {
      ++failed[outcome.phase + (outcome.reason.empty() ? "" : ":" + outcome.reason)];
      if (!options.dump.empty()) {
        std::ofstream(options.dump + "/goal_" + std::to_string(i) + ".strata", std::ios::binary) << map_file;
        // The map the goal failed on: a way blocked on the drive is in this one, not in the one before.
        std::ofstream(options.dump + "/goal_" + std::to_string(i) + "_end.strata", std::ios::binary)
            << download_map(port);
      }
    }
    std::printf(
        "goal i=%d from=%.2f,%.2f,%.2f to=%.2f,%.2f,%.2f distance=%.1f candidates=%zu phase=%s reason=%s "
        "accepted=%d seconds=%.1f error_m=%.2f pose_xy_m=%.2f pose_z_m=%.2f%s%s%s\n",
        i, robot.x(), robot.y(), robot.z(), goal.x(), goal.y(), goal.z(),
        std::hypot(goal.x() - robot.x(), goal.y() - robot.y()), spots.size(), outcome.phase.c_str(),
        outcome.reason.empty() ? "-" : outcome.reason.c_str(), outcome.accepted ? 1 : 0, outcome.seconds,
        (end - goal).head<2>().norm(), (estimate - robot).head<2>().norm(), estimate.z() - robot.z(),
        outcome.message.empty() ? "" : " message=\"", outcome.message.c_str(),
        outcome.message.empty() ? "" : "\"");
    std::fflush(stdout);
  }
  // How much of the scan stream the robot's localizer kept up with (a busy machine drops scans).
  const auto metrics = http_request(port, http::verb::get, "/metrics", {}, kTestOperatorToken).body();
  const auto counter = [&](const std::string& name) {
    const std::size_t at = metrics.find("\n" + name + " ");
    return at == std::string::npos ? -1.0 : std::atof(metrics.c_str() + at + name.size() + 2);
  };
  std::string reasons;
  for (const auto& [reason, count] : failed)
    reasons += " " + reason + "=" + std::to_string(count);
  std::printf(
      "summary world=%s scanner=%s warmup=%.0f tried=%d accepted=%d reached=%d accepted_share=%.2f "
      "reached_share=%.2f scans=%.0f scans_dropped=%.0f%s\n",
      options.world.c_str(), options.scanner.c_str(), options.warmup, tried, accepted, reached,
      tried > 0 ? static_cast<double>(accepted) / tried : 0.0,
      tried > 0 ? static_cast<double>(reached) / tried : 0.0, counter("strata_scans_total"),
      counter("strata_scans_dropped_total"), reasons.c_str());
  return 0;
}

#include "server/app/register_command.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/geometry/pose.hpp"
#include "core/geometry/pose_text.hpp"
#include "core/registration/register_scan.hpp"
#include "drivers/io/point_cloud_file.hpp"

namespace strata::app {
namespace {

constexpr const char* kGuessSyntax =
    "--guess needs x,y,z or x,y,z,roll,pitch,yaw (metres, degrees), or the old six numbers "
    "\"x y z roll pitch yaw\" (metres, radians)";

/// The old form, before the command line had one pose syntax: six numbers, spaces, radians.
Pose3 parse_old_guess(const std::string& text) {
  std::istringstream in(text);
  Pose3 pose;
  std::string extra;
  if (!(in >> pose.position.x() >> pose.position.y() >> pose.position.z() >> pose.roll >> pose.pitch >>
        pose.yaw) ||
      (in >> extra))
    throw std::invalid_argument(kGuessSyntax);
  constexpr double kDegrees = 180.0 / std::numbers::pi;
  spdlog::warn(
      "--guess \"{}\" is the old form (spaces, radians); write --guess {},{},{},{},{},{} (metres, degrees)",
      text, pose.position.x(), pose.position.y(), pose.position.z(), pose.roll * kDegrees,
      pose.pitch * kDegrees, pose.yaw * kDegrees);
  return pose;
}

Eigen::Isometry3d parse_guess(const std::string& text) {
  if (text.empty())
    return Eigen::Isometry3d::Identity();
  if (text.find(',') == std::string::npos)
    return parse_old_guess(text).to_isometry();
  try {
    return parse_pose_text(text).to_isometry();
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string(kGuessSyntax) + ": " + error.what());
  }
}

}  // namespace

CLI::App* add_register_command(CLI::App& app, RegisterOptions& options) {
  auto* command = app.add_subcommand(
      "register",
      "Register SOURCE onto TARGET with ICP and print the 4x4 transform that maps source points into the\n"
      "target frame, with RMSE, pairs, iterations, verdict and time. Formats by extension: .pcd, .ply,\n"
      ".3d (3DTK: cm, left-handed; converted), .csv/.xyz/.txt. Exit code 3 when fault control rejects.");
  command->add_option("source", options.source, "Scan to move")->required()->check(CLI::ExistingFile);
  command->add_option("target", options.target, "Scan to move it onto")->required()->check(CLI::ExistingFile);
  command->add_option(
      "--guess", options.guess,
      "Initial source-to-target pose x,y,z[,roll,pitch,yaw] in metres and degrees, like --lidar-mount "
      "(default identity; the old \"x y z roll pitch yaw\" in radians still works, with a warning)");
  command->add_flag("--json", options.json, "Print one JSON object instead of text");
  return command;
}

int run_register(const RegisterOptions& options) {
  const Eigen::Isometry3d guess = parse_guess(options.guess);
  const io::LoadedCloud source = io::read_point_cloud(options.source);
  const io::LoadedCloud target = io::read_point_cloud(options.target);
  const RegistrationResult result = register_scan(source.points, target.points, guess);

  const Eigen::Matrix4d m = result.refined.matrix();
  const Pose3 pose = Pose3::from_isometry(result.refined);
  if (options.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
    const nlohmann::json out{
        {"transform", rows},
        {"pose",
         {{"x", pose.position.x()},
          {"y", pose.position.y()},
          {"z", pose.position.z()},
          {"roll", pose.roll},
          {"pitch", pose.pitch},
          {"yaw", pose.yaw}}},
        {"rmse", result.rmse},
        {"pairs", result.pairs},
        {"iterations", result.iterations},
        {"converged", result.converged},
        {"verdict", to_string(result.assessment.verdict)},
        {"reason", to_string(result.assessment.reason)},
        {"message", result.assessment.message},
        {"seconds", result.seconds},
        {"source_points",
         {{"read", source.points.size()},
          {"dropped", source.dropped_non_finite},
          {"used", result.source_points}}},
        {"target_points",
         {{"read", target.points.size()},
          {"dropped", target.dropped_non_finite},
          {"used", result.target_points}}},
    };
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("transform (source -> target):\n");
    for (int r = 0; r < 4; ++r)
      std::printf("  % .6f % .6f % .6f % .6f\n", m(r, 0), m(r, 1), m(r, 2), m(r, 3));
    std::printf("pose: x %.4f y %.4f z %.4f roll %.4f pitch %.4f yaw %.4f (m, rad)\n", pose.position.x(),
                pose.position.y(), pose.position.z(), pose.roll, pose.pitch, pose.yaw);
    std::printf("rmse: %.4f m\npairs: %zu of %zu source points\niterations: %d\ntime: %.1f ms\n", result.rmse,
                result.pairs, result.source_points, result.iterations, 1e3 * result.seconds);
    std::printf("verdict: %s", std::string(to_string(result.assessment.verdict)).c_str());
    if (!result.accepted())
      std::printf(" (%s: %s)", std::string(to_string(result.assessment.reason)).c_str(),
                  result.assessment.message.c_str());
    std::printf("\n");
  }
  return result.accepted() ? 0 : 3;
}

}  // namespace strata::app

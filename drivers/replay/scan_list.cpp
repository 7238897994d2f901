#include "drivers/replay/scan_list.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>

#include "drivers/replay/csv_table.hpp"

namespace strata::replay {
namespace {

constexpr double kMaxRays = 1e9;

/// The gravity reading in columns up_x, up_y, up_z (which way is up, base frame) and up_sigma (radians).
GravityReading read_gravity(const CsvTable& table, std::size_t row, const std::string& name) {
  GravityReading gravity;
  gravity.up_in_base = {table.number(row, "up_x"), table.number(row, "up_y"), table.number(row, "up_z")};
  gravity.sigma = table.number(row, "up_sigma");
  const double norm = gravity.up_in_base.norm();
  if (!std::isfinite(norm) || norm < 0.5 || norm > 2.0 || !std::isfinite(gravity.sigma) ||
      gravity.sigma <= 0.0)
    throw DatasetError(fmt::format(
        "{}: scan {}: the gravity reading ({}, {}, {}; sigma {}) is not a direction "
        "with a positive sigma",
        name, row, gravity.up_in_base.x(), gravity.up_in_base.y(), gravity.up_in_base.z(), gravity.sigma));
  if (std::abs(norm - 1.0) > 1e-9)  // a recording's unit vector reads back bit for bit
    gravity.up_in_base /= norm;
  return gravity;
}

/// What the gyro read standing, in columns gyro_rate (rad/s), gyro_seconds and gyro_sigma (rad/s).
StandingGyro read_standing_gyro(const CsvTable& table, std::size_t row, const std::string& name) {
  const StandingGyro gyro{.rate = table.number(row, "gyro_rate"),
                          .seconds = table.number(row, "gyro_seconds"),
                          .sigma = table.number(row, "gyro_sigma")};
  if (!gyro.usable())
    throw DatasetError(
        fmt::format("{}: scan {}: the standing gyro reading ({} rad/s over {} s; sigma {}) "
                    "needs a finite rate, positive seconds and a positive sigma",
                    name, row, gyro.rate, gyro.seconds, gyro.sigma));
  return gyro;
}

}  // namespace

std::vector<DatasetScan> parse_scan_list(std::istream& csv, const std::filesystem::path& directory,
                                         const std::string& source) {
  const CsvTable table(csv, source);
  for (const char* required : {"file", "stamp"}) {
    if (!table.has(required))
      throw DatasetError(source + ": no column '" + required + "'");
  }
  std::vector<DatasetScan> scans;
  for (std::size_t row = 0; row < table.size(); ++row) {
    DatasetScan scan;
    scan.file = directory / table.text(row, "file");
    scan.stamp = table.number(row, "stamp");
    scan.odometry = table.pose(row, "");
    scan.reference = table.pose(row, "truth_");
    if (table.has("duration"))
      scan.duration = table.number(row, "duration");
    if (table.has("sensor"))
      scan.sensor = table.text(row, "sensor");
    if (table.has("rays")) {
      // Beyond a count's range the conversion would be undefined (a fuzzed list found it); no scan has a
      // billion beams.
      const double rays = table.number(row, "rays");
      if (rays > kMaxRays)
        throw DatasetError(
            fmt::format("{}: scan {}: {} rays is beyond any scan's ({:g})", source, row, rays, kMaxRays));
      scan.rays = static_cast<std::size_t>(std::max(0.0, rays));
    }
    if (table.has("max_range"))
      scan.max_range = table.number(row, "max_range");
    if (table.has("mount_00")) {
      std::vector<double> mount;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c)
          mount.push_back(table.number(row, fmt::format("mount_{}{}", r, c)));
      }
      scan.sensor_to_base = transform_from_row_major(mount);
    } else {
      scan.mount_known = false;
    }
    if (table.has("up_x") && !table.text(row, "up_x").empty())
      scan.gravity = read_gravity(table, row, source);
    if (table.has("gyro_rate") && !table.text(row, "gyro_rate").empty())
      scan.standing_gyro = read_standing_gyro(table, row, source);
    if (!scans.empty() && scan.stamp < scans.back().stamp)
      throw DatasetError(fmt::format("{}: scan {} is older than the one before it", source, row));
    scans.push_back(std::move(scan));
  }
  if (scans.empty())
    throw DatasetError(source + ": no scans");
  return scans;
}

Eigen::Isometry3d transform_from_row_major(const std::vector<double>& values) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      transform.matrix()(row, col) = values[static_cast<std::size_t>(row * 4 + col)];
  }
  return transform;
}

}  // namespace strata::replay

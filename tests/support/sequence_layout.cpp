#include "support/sequence_layout.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace strata::test {
namespace fs = std::filesystem;
namespace {

struct Entry {
  fs::path file;
  double stamp = 0.0;
  Eigen::Isometry3d reference = Eigen::Isometry3d::Identity();
};

std::vector<double> numbers_of(std::string line) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::istringstream in(line);
  std::vector<double> values;
  for (double value = 0.0; in >> value;)
    values.push_back(value);
  return values;
}

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path.string() + ": cannot read");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") != std::string::npos)
      lines.push_back(line);
  }
  return lines;
}

Eigen::Isometry3d from_rows(const std::vector<double>& r) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col)
      m(row, col) = r[static_cast<std::size_t>(4 * row + col)];
  Eigen::Isometry3d pose(m);
  // The references are SLAM outputs in text: make the rotation exactly orthonormal.
  pose.linear() = Eigen::Quaterniond(pose.rotation()).normalized().toRotationMatrix();
  return pose;
}

std::vector<Entry> balm(const fs::path& dir) {
  const auto lines = lines_of(dir / "alidarPose.csv");
  std::vector<Entry> entries;
  for (std::size_t k = 0; 4 * k + 3 < lines.size(); ++k) {
    std::vector<double> rows;
    for (std::size_t i = 0; i < 3; ++i) {
      const auto row = numbers_of(lines[4 * k + i]);
      if (row.size() < 4)
        throw std::runtime_error(
            fmt::format("{}: scan {}: a pose row of fewer than 4 numbers", dir.string(), k));
      rows.insert(rows.end(), row.begin(), row.begin() + 4);
    }
    const auto last = numbers_of(lines[4 * k + 3]);
    if (last.size() < 4)
      throw std::runtime_error(fmt::format("{}: scan {}: no stamp", dir.string(), k));
    const fs::path file = dir / fmt::format("full{}.pcd", k);
    if (!fs::exists(file))
      break;
    entries.push_back({fs::absolute(file), last[3], from_rows(rows)});
  }
  return entries;
}

std::vector<Entry> keyframes(const fs::path& dir) {
  const auto poses = lines_of(dir / "optimized_poses.txt");
  const auto times = lines_of(dir / "times.txt");
  std::vector<Entry> entries;
  for (std::size_t k = 0; k < poses.size() && k < times.size(); ++k) {
    const auto row = numbers_of(poses[k]);
    if (row.size() != 12)
      throw std::runtime_error(fmt::format("{}: keyframe {}: not 12 numbers", dir.string(), k));
    entries.push_back({fs::absolute(dir / "Scans" / fmt::format("{:06d}.pcd", k)), numbers_of(times[k]).at(0),
                       from_rows(row)});
  }
  return entries;
}

/// A scans.csv's every n-th row, its files made absolute.
fs::path thinned_scan_list(const fs::path& dir, const fs::path& scratch, std::size_t every) {
  const auto lines = lines_of(dir / "scans.csv");
  fs::create_directories(scratch);
  std::ofstream out(scratch / "scans.csv");
  out << lines.at(0) << "\n";
  const std::size_t file_column = [&] {
    std::istringstream header(lines.at(0));
    std::size_t column = 0;
    for (std::string name; std::getline(header, name, ','); ++column) {
      if (name == "file")
        return column;
    }
    throw std::runtime_error((dir / "scans.csv").string() + ": no file column");
  }();
  for (std::size_t row = 1; row < lines.size(); row += every) {
    std::istringstream in(lines[row]);
    std::string cell;
    for (std::size_t column = 0; std::getline(in, cell, ','); ++column) {
      out << (column == 0 ? "" : ",") << (column == file_column ? fs::absolute(dir / cell).string() : cell);
    }
    out << "\n";
  }
  return scratch;
}

}  // namespace

fs::path scan_list_for(const fs::path& dir, const fs::path& scratch, std::size_t every) {
  every = std::max<std::size_t>(every, 1);
  if (fs::exists(dir / "scans.csv"))
    return every == 1 ? dir : thinned_scan_list(dir, scratch, every);
  std::vector<Entry> entries;
  if (fs::exists(dir / "alidarPose.csv"))
    entries = balm(dir);
  else if (fs::exists(dir / "optimized_poses.txt") && fs::exists(dir / "times.txt"))
    entries = keyframes(dir);
  else
    throw std::runtime_error(dir.string() + ": no scans.csv, alidarPose.csv or optimized_poses.txt");
  if (entries.empty())
    throw std::runtime_error(dir.string() + ": no scans");
  fs::create_directories(scratch);
  std::ofstream out(scratch / "scans.csv");
  out << "file,stamp,truth_x,truth_y,truth_z,truth_roll,truth_pitch,truth_yaw\n";
  for (std::size_t i = 0; i < entries.size(); i += every) {
    const Entry& entry = entries[i];
    const Pose3 pose = Pose3::from_isometry(entry.reference);
    out << fmt::format("{},{:.6f},{:.9g},{:.9g},{:.9g},{:.12g},{:.12g},{:.12g}\n", entry.file.string(),
                       entry.stamp, pose.position.x(), pose.position.y(), pose.position.z(), pose.roll,
                       pose.pitch, pose.yaw);
  }
  if (!out)
    throw std::runtime_error((scratch / "scans.csv").string() + ": cannot write");
  return scratch;
}

}  // namespace strata::test

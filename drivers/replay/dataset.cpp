#include "drivers/replay/dataset.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>

#include "drivers/io/json_input.hpp"
#include "drivers/io/kitti_reader.hpp"
#include "drivers/io/point_cloud_file.hpp"
#include "drivers/io/text_fields.hpp"
#include "drivers/io/threedtk_reader.hpp"
#include "drivers/replay/recording_layout.hpp"

namespace strata::replay {
namespace fs = std::filesystem;

namespace {

/// 3DTK's example data has no clock: stop-and-go scans are played this far apart (seconds).
constexpr double kThreeDtkScanPeriod = 5.0;
/// KITTI without times.txt: the Velodyne's 10 Hz.
constexpr double kKittiScanPeriod = 0.1;

bool is_file(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

/// The rows of a CSV file with a header row, each as column name -> field. Throws DatasetError.
class CsvTable {
 public:
  explicit CsvTable(const fs::path& path) : path_(path) {
    std::ifstream in(path);
    if (!in)
      throw DatasetError(path.string() + ": cannot open");
    std::string line;
    if (!std::getline(in, line))
      throw DatasetError(path.string() + ": empty (expected a header row)");
    for (const std::string_view name : io::split_fields(line))
      columns_.emplace_back(name);
    for (std::size_t number = 2; std::getline(in, line); ++number) {
      if (io::trimmed(line).empty())
        continue;
      std::vector<std::string> row;
      for (const std::string_view field : io::split_fields(line))
        row.emplace_back(field);
      if (row.size() != columns_.size()) {
        throw DatasetError(fmt::format("{}: line {} has {} fields, the header {}", path.string(), number,
                                       row.size(), columns_.size()));
      }
      rows_.push_back(std::move(row));
      lines_.push_back(number);
    }
  }

  [[nodiscard]] std::size_t size() const { return rows_.size(); }
  [[nodiscard]] bool has(const std::string& column) const { return index(column).has_value(); }
  /// The field as text; throws when the column is missing.
  [[nodiscard]] const std::string& text(std::size_t row, const std::string& column) const {
    const auto i = index(column);
    if (!i)
      throw DatasetError(path_.string() + ": no column '" + column + "'");
    return rows_[row][*i];
  }
  /// The field as a finite number; throws naming the line otherwise.
  [[nodiscard]] double number(std::size_t row, const std::string& column) const {
    const std::string& field = text(row, column);
    const auto value = io::parse_number(field);
    if (!value || !std::isfinite(*value)) {
      throw DatasetError(
          fmt::format("{}: line {}: {} '{}' is not a number", path_.string(), lines_[row], column, field));
    }
    return *value;
  }
  /// The pose in columns prefix+x ... prefix+yaw: nothing when the columns are missing or all empty.
  [[nodiscard]] std::optional<Pose3> pose(std::size_t row, const std::string& prefix) const {
    static const char* const kNames[] = {"x", "y", "z", "roll", "pitch", "yaw"};
    if (!has(prefix + "x"))
      return std::nullopt;
    if (text(row, prefix + "x").empty())
      return std::nullopt;
    double values[6];
    for (std::size_t i = 0; i < 6; ++i)
      values[i] = number(row, prefix + kNames[i]);
    Pose3 pose;
    pose.position = Eigen::Vector3d(values[0], values[1], values[2]);
    pose.roll = values[3];
    pose.pitch = values[4];
    pose.yaw = values[5];
    return pose;
  }

 private:
  [[nodiscard]] std::optional<std::size_t> index(const std::string& column) const {
    const auto it = std::find(columns_.begin(), columns_.end(), column);
    if (it == columns_.end())
      return std::nullopt;
    return static_cast<std::size_t>(it - columns_.begin());
  }

  fs::path path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<std::size_t> lines_;
};

Eigen::Isometry3d from_row_major(const std::vector<double>& values) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      transform.matrix()(row, col) = values[static_cast<std::size_t>(row * 4 + col)];
  }
  return transform;
}

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

/// scans.csv (a recording, or a hand-made list of point files).
std::vector<DatasetScan> read_scan_list(const fs::path& directory) {
  const CsvTable table(directory / kScansFile);
  const std::string name = (directory / kScansFile).string();
  for (const char* required : {"file", "stamp"}) {
    if (!table.has(required))
      throw DatasetError(name + ": no column '" + required + "'");
  }
  std::vector<DatasetScan> scans;
  for (std::size_t row = 0; row < table.size(); ++row) {
    DatasetScan scan;
    scan.file = directory / table.text(row, "file");
    if (!is_file(scan.file))
      throw DatasetError(name + ": scan file " + scan.file.string() + " does not exist");
    scan.stamp = table.number(row, "stamp");
    scan.odometry = table.pose(row, "");
    scan.reference = table.pose(row, "truth_");
    if (table.has("duration"))
      scan.duration = table.number(row, "duration");
    if (table.has("sensor"))
      scan.sensor = table.text(row, "sensor");
    if (table.has("rays"))
      scan.rays = static_cast<std::size_t>(std::max(0.0, table.number(row, "rays")));
    if (table.has("max_range"))
      scan.max_range = table.number(row, "max_range");
    if (table.has("mount_00")) {
      std::vector<double> mount;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c)
          mount.push_back(table.number(row, fmt::format("mount_{}{}", r, c)));
      }
      scan.sensor_to_base = from_row_major(mount);
    } else {
      scan.mount_known = false;
    }
    if (table.has("up_x") && !table.text(row, "up_x").empty())
      scan.gravity = read_gravity(table, row, name);
    if (table.has("gyro_rate") && !table.text(row, "gyro_rate").empty())
      scan.standing_gyro = read_standing_gyro(table, row, name);
    if (!scans.empty() && scan.stamp < scans.back().stamp)
      throw DatasetError(fmt::format("{}: scan {} is older than the one before it", name, row));
    scans.push_back(std::move(scan));
  }
  if (scans.empty())
    throw DatasetError(name + ": no scans");
  return scans;
}

std::vector<DatasetOdometry> read_odometry_stream(const fs::path& path) {
  const CsvTable table(path);
  std::vector<DatasetOdometry> samples;
  for (std::size_t row = 0; row < table.size(); ++row) {
    DatasetOdometry sample;
    sample.stamp = table.number(row, "stamp");
    const auto odometry = table.pose(row, "");
    if (!odometry)
      throw DatasetError(fmt::format("{}: row {} has no odometry pose", path.string(), row + 1));
    sample.odometry = *odometry;
    sample.reference = table.pose(row, "truth_");
    samples.push_back(sample);
  }
  return samples;
}

Dataset read_recording(const fs::path& directory, bool with_metadata) {
  Dataset dataset;
  dataset.layout = with_metadata ? DatasetLayout::kRecording : DatasetLayout::kScanList;
  dataset.directory = directory;
  dataset.scans = read_scan_list(directory);
  if (is_file(directory / kOdometryFile))
    dataset.odometry = read_odometry_stream(directory / kOdometryFile);
  std::string source = "a list of point files";
  if (with_metadata) {
    const fs::path path = directory / kRecordingFile;
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const io::JsonInput input = io::parse_json(text);
    if (!input.ok())
      throw DatasetError(path.string() + ": " + input.error);
    const nlohmann::json& metadata = input.value;
    if (!metadata.is_object() || metadata.value("format", "") != kRecordingFormat)
      throw DatasetError(path.string() + ": not a Strata recording (format '" +
                         std::string(kRecordingFormat) + "')");
    if (metadata.value("version", 0) != kRecordingVersion) {
      throw DatasetError(fmt::format("{}: recording version {} (this Strata reads version {})", path.string(),
                                     metadata.value("version", 0), kRecordingVersion));
    }
    if (metadata.contains("initial_map_from_odom")) {
      const auto& values = metadata["initial_map_from_odom"];
      if (!values.is_array() || values.size() != 12 ||
          !std::all_of(values.begin(), values.end(), [](const auto& v) { return v.is_number(); }))
        throw DatasetError(path.string() + ": initial_map_from_odom is not 12 numbers (3x4 row-major)");
      dataset.initial_map_from_odom = from_row_major(values.get<std::vector<double>>());
    }
    source = "a Strata recording of " + metadata.value("source", std::string("?"));
    for (DatasetScan& scan : dataset.scans)
      scan.times_from_stamp = true;  // what the recorder writes (encode_binary_pcd)
  }
  dataset.description = fmt::format("{} ({} scans, {} odometry samples)", source, dataset.scans.size(),
                                    dataset.odometry.size());
  return dataset;
}

/// The numbered files `prefix` NNN `extension` in `directory`, by number.
std::map<long, fs::path> numbered_files(const fs::path& directory, const std::string& pattern) {
  std::map<long, fs::path> files;
  const std::regex name_pattern(pattern);
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, match, name_pattern))
      files[std::stol(match[1].str())] = entry.path();
  }
  return files;
}

Dataset read_threedtk(const fs::path& directory) {
  Dataset dataset;
  dataset.layout = DatasetLayout::kThreeDtk;
  dataset.directory = directory;
  const auto scans = numbered_files(directory, R"(scan(\d+)\.3d)");
  // Reference poses (slam6D's .frames) next to the scans or in one subdirectory.
  std::vector<fs::path> frame_dirs{directory};
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    if (entry.is_directory())
      frame_dirs.push_back(entry.path());
  }
  std::sort(frame_dirs.begin() + 1, frame_dirs.end());
  fs::path frames_from;
  for (const fs::path& candidate : frame_dirs) {
    if (!numbered_files(candidate, R"(scan(\d+)\.frames)").empty()) {
      frames_from = candidate;
      break;
    }
  }
  std::size_t references = 0;
  for (const auto& [number, file] : scans) {
    DatasetScan scan;
    scan.file = file;
    scan.stamp = static_cast<double>(dataset.scans.size()) * kThreeDtkScanPeriod;
    scan.sensor = "3dtk";
    fs::path pose_file = file;
    pose_file.replace_extension(".pose");
    if (!is_file(pose_file))
      throw DatasetError(file.string() + " has no odometry pose " + pose_file.filename().string());
    try {
      scan.odometry = Pose3::from_isometry(io::read_3dtk_pose(pose_file));
      if (!frames_from.empty()) {
        const fs::path frames = frames_from / file.filename().replace_extension(".frames");
        if (is_file(frames)) {
          scan.reference = Pose3::from_isometry(io::read_3dtk_frames(frames));
          ++references;
        }
      }
    } catch (const std::exception& e) {
      throw DatasetError(e.what());
    }
    dataset.scans.push_back(std::move(scan));
  }
  if (references != 0 && references != dataset.scans.size()) {
    throw DatasetError(
        fmt::format("{}: {} .frames files for {} scans (a reference pose for every scan, or none)",
                    frames_from.string(), references, dataset.scans.size()));
  }
  dataset.description =
      fmt::format("3DTK scans ({}, odometry from .pose{})", dataset.scans.size(),
                  references ? ", reference poses from " + frames_from.filename().string() : "");
  return dataset;
}

Dataset read_kitti(const fs::path& directory) {
  Dataset dataset;
  dataset.layout = DatasetLayout::kKitti;
  dataset.directory = directory;
  const auto files = numbered_files(directory / "velodyne", R"((\d+)\.bin)");
  const fs::path poses_file = directory / "poses.txt";
  if (!is_file(poses_file))
    throw DatasetError(directory.string() +
                       ": KITTI velodyne scans without poses.txt (a pose for every scan)");
  try {
    const std::vector<Eigen::Isometry3d> camera_poses = io::read_kitti_poses(poses_file);
    if (camera_poses.size() != files.size()) {
      throw DatasetError(fmt::format("{}: {} poses for {} velodyne scans", poses_file.string(),
                                     camera_poses.size(), files.size()));
    }
    std::optional<Eigen::Isometry3d> velodyne_to_camera;
    if (is_file(directory / "calib.txt"))
      velodyne_to_camera = io::read_kitti_velodyne_to_camera(directory / "calib.txt");
    const auto poses = io::kitti_velodyne_poses(camera_poses, velodyne_to_camera);
    std::vector<double> times;
    if (is_file(directory / "times.txt")) {
      times = io::read_kitti_times(directory / "times.txt");
      if (times.size() != files.size()) {
        throw DatasetError(fmt::format("{}: {} times for {} velodyne scans",
                                       (directory / "times.txt").string(), times.size(), files.size()));
      }
    }
    std::size_t i = 0;
    for (const auto& [number, file] : files) {
      DatasetScan scan;
      scan.file = file;
      scan.stamp = times.empty() ? static_cast<double>(i) * kKittiScanPeriod : times[i];
      scan.sensor = "kitti-velodyne";
      scan.reference = Pose3::from_isometry(poses[i]);  // ground truth; the dataset has no odometry
      if (!dataset.scans.empty() && scan.stamp < dataset.scans.back().stamp)
        throw DatasetError(fmt::format("{}: scan {} is older than the one before it", directory.string(), i));
      dataset.scans.push_back(std::move(scan));
      ++i;
    }
    dataset.description =
        fmt::format("KITTI velodyne scans ({}, reference poses from poses.txt{}{})", dataset.scans.size(),
                    velodyne_to_camera ? ", calib.txt" : "", times.empty() ? "" : ", times.txt");
  } catch (const DatasetError&) {
    throw;
  } catch (const std::exception& e) {
    throw DatasetError(e.what());
  }
  return dataset;
}

}  // namespace

std::string to_string(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kRecording:
      return "recording";
    case DatasetLayout::kScanList:
      return "scan-list";
    case DatasetLayout::kThreeDtk:
      return "3dtk";
    case DatasetLayout::kKitti:
      return "kitti";
  }
  return "unknown";
}

Dataset open_dataset(const fs::path& directory) {
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw DatasetError(directory.string() + ": not a directory");
  if (is_file(directory / kRecordingFile))
    return read_recording(directory, true);
  if (is_file(directory / kScansFile))
    return read_recording(directory, false);
  if (!numbered_files(directory, R"(scan(\d+)\.3d)").empty())
    return read_threedtk(directory);
  if (fs::is_directory(directory / "velodyne", error) &&
      !numbered_files(directory / "velodyne", R"((\d+)\.bin)").empty())
    return read_kitti(directory);
  throw DatasetError(directory.string() +
                     ": no dataset Strata can replay (expected recording.json or scans.csv with point files, "
                     "scanNNN.3d with scanNNN.pose (3DTK), or velodyne/NNNNNN.bin with poses.txt (KITTI))");
}

std::vector<Eigen::Vector3f> load_points(const DatasetScan& scan, std::vector<float>* times) {
  io::LoadedCloud cloud;
  try {
    cloud = scan.file.extension() == ".bin" ? io::read_kitti_velodyne(scan.file)
                                            : io::read_point_cloud(scan.file);
  } catch (const std::exception& e) {
    throw DatasetError(e.what());
  }
  std::vector<Eigen::Vector3f> points;
  points.reserve(cloud.points.size());
  for (const Eigen::Vector3d& point : cloud.points)
    points.push_back(point.cast<float>());
  if (times != nullptr) {
    times->clear();
    if (scan.times_from_stamp && cloud.times.size() == points.size())
      *times = std::move(cloud.times);
  }
  return points;
}

}  // namespace strata::replay

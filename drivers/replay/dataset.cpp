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
#include "drivers/io/threedtk_reader.hpp"
#include "drivers/replay/csv_table.hpp"
#include "drivers/replay/mcap_dataset.hpp"
#include "drivers/replay/recording_layout.hpp"
#include "drivers/replay/scan_list.hpp"

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

std::ifstream open_csv(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw DatasetError(path.string() + ": cannot open");
  return in;
}

/// scans.csv (a recording, or a hand-made list of point files), with every point file it lists in place.
std::vector<DatasetScan> read_scan_list(const fs::path& directory) {
  const fs::path path = directory / kScansFile;
  std::ifstream in = open_csv(path);
  std::vector<DatasetScan> scans = parse_scan_list(in, directory, path.string());
  for (const DatasetScan& scan : scans) {
    if (!is_file(scan.file))
      throw DatasetError(path.string() + ": scan file " + scan.file.string() + " does not exist");
  }
  return scans;
}

std::vector<DatasetOdometry> read_odometry_stream(const fs::path& path) {
  std::ifstream in = open_csv(path);
  return parse_odometry_stream(in, path.string());
}

Dataset read_recording(const fs::path& directory, bool with_metadata) {
  Dataset dataset;
  dataset.layout = with_metadata ? DatasetLayout::kRecording : DatasetLayout::kScanList;
  dataset.directory = directory;
  dataset.scans = read_scan_list(directory);
  if (is_file(directory / kOdometryFile))
    dataset.odometry = read_odometry_stream(directory / kOdometryFile);
  dataset.description = fmt::format("a list of point files ({} scans, {} odometry samples)",
                                    dataset.scans.size(), dataset.odometry.size());
  if (with_metadata) {
    const fs::path path = directory / kRecordingFile;
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    read_recording_metadata(text, path.string(), kRecordingFormat, kRecordingVersion, dataset);
  }
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

std::vector<DatasetOdometry> parse_odometry_stream(std::istream& csv, const std::string& source) {
  const CsvTable table(csv, source);
  std::vector<DatasetOdometry> samples;
  for (std::size_t row = 0; row < table.size(); ++row) {
    DatasetOdometry sample;
    sample.stamp = table.number(row, "stamp");
    const auto odometry = table.pose(row, "");
    if (!odometry)
      throw DatasetError(fmt::format("{}: row {} has no odometry pose", source, row + 1));
    sample.odometry = *odometry;
    sample.reference = table.pose(row, "truth_");
    samples.push_back(sample);
  }
  return samples;
}

void read_recording_metadata(const std::string& text, const std::string& source, std::string_view format,
                             int version, Dataset& dataset) {
  const io::JsonInput input = io::parse_json(text);
  if (!input.ok())
    throw DatasetError(source + ": " + input.error);
  const nlohmann::json& metadata = input.value;
  if (!metadata.is_object() || metadata.value("format", "") != format)
    throw DatasetError(source + ": not a Strata recording (format '" + std::string(format) + "')");
  if (metadata.value("version", 0) != version) {
    throw DatasetError(fmt::format("{}: recording version {} (this Strata reads version {})", source,
                                   metadata.value("version", 0), version));
  }
  if (metadata.contains("initial_map_from_odom")) {
    const auto& values = metadata["initial_map_from_odom"];
    if (!values.is_array() || values.size() != 12 ||
        !std::all_of(values.begin(), values.end(), [](const auto& v) { return v.is_number(); }))
      throw DatasetError(source + ": initial_map_from_odom is not 12 numbers (3x4 row-major)");
    dataset.initial_map_from_odom = transform_from_row_major(values.get<std::vector<double>>());
  }
  for (DatasetScan& scan : dataset.scans)
    scan.times_from_stamp = true;  // what the recorder writes (encode_binary_pcd, the /scan time field)
  dataset.description =
      fmt::format("a Strata recording of {} ({} scans, {} odometry samples)",
                  metadata.value("source", std::string("?")), dataset.scans.size(), dataset.odometry.size());
}

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
    case DatasetLayout::kMcap:
      return "mcap";
  }
  return "unknown";
}

Dataset open_dataset(const fs::path& directory) {
  std::error_code error;
  if (directory.extension() == ".mcap" && !fs::is_directory(directory, error))
    return open_mcap_recording(directory);
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
  if (scan.store)
    return scan.store->points(scan.store_index, times);
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

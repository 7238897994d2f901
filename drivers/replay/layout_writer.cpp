#include "drivers/replay/layout_writer.hpp"

#include <chrono>
#include <stdexcept>
#include <utility>

#include "core/files/atomic_file.hpp"
#include "drivers/io/pcd_writer.hpp"
#include "drivers/replay/recording_layout.hpp"

namespace strata::replay {
namespace fs = std::filesystem;

namespace {

std::ofstream open_csv(const fs::path& path, const std::string& header) {
  std::ofstream out(path, std::ios::out | std::ios::trunc);
  out << header;
  out.flush();
  if (!out)
    throw std::runtime_error("cannot write " + path.string());
  return out;
}

}  // namespace

nlohmann::json recording_metadata(const nlohmann::json& metadata,
                                  const Eigen::Isometry3d& initial_map_from_odom) {
  nlohmann::json result = metadata;
  result["format"] = kRecordingFormat;
  result["version"] = kRecordingVersion;
  nlohmann::json matrix = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      matrix.push_back(initial_map_from_odom.matrix()(row, col));
  }
  result["initial_map_from_odom"] = std::move(matrix);
  result["started_at"] =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  return result;
}

LayoutWriter::LayoutWriter(fs::path directory, const nlohmann::json& metadata,
                           const Eigen::Isometry3d& initial_map_from_odom)
    : directory_(std::move(directory)), metadata_(recording_metadata(metadata, initial_map_from_odom)) {
  std::error_code error;
  if (fs::exists(directory_ / kRecordingFile, error) || fs::exists(directory_ / kScansFile, error))
    throw std::runtime_error(directory_.string() +
                             " already holds a recording (record into a new directory)");
  fs::create_directories(directory_ / kScansDirectory, error);
  if (error)
    throw std::runtime_error("cannot create " + (directory_ / kScansDirectory).string() + ": " +
                             error.message());
  try {
    write_metadata(false, {});
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("cannot start the recording: ") + e.what());
  }
  scans_csv_ = open_csv(directory_ / kScansFile, scans_csv_header());
  odometry_csv_ = open_csv(directory_ / kOdometryFile, odometry_csv_header());
}

void LayoutWriter::write(const RobotSample& sample) {
  odometry_csv_ << odometry_csv_row(sample);
  odometry_csv_.flush();
  if (!odometry_csv_)
    throw std::runtime_error("cannot write " + (directory_ / kOdometryFile).string());
}

void LayoutWriter::write(const ScanEvent& scan) {
  // Numbered by attempt, so a failed write never makes a later scan reuse (or fight over) its name.
  const std::string file = scan_file_name(next_scan_file_++);
  // The scan file first, then its row: every listed scan exists.
  write_file_atomically(directory_ / file, io::encode_binary_pcd(scan.points, scan.point_times),
                        Durability::kOrdered);
  scans_csv_ << scans_csv_row(scan, file);
  scans_csv_.flush();
  if (!scans_csv_)
    throw std::runtime_error("cannot write " + (directory_ / kScansFile).string());
}

void LayoutWriter::finish(const RecorderStatus& status) {
  write_metadata(true, status);
}

void LayoutWriter::write_metadata(bool finished, const RecorderStatus& status) {
  nlohmann::json metadata = metadata_;
  metadata["finished"] = finished;
  metadata["scans"] = status.scans;
  metadata["samples"] = status.samples;
  metadata["dropped"] = status.dropped;
  metadata["errors"] = status.errors;
  write_file_atomically(directory_ / kRecordingFile, metadata.dump(2) + "\n", Durability::kOrdered);
}

}  // namespace strata::replay

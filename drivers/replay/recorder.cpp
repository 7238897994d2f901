#include "drivers/replay/recorder.hpp"

#include <spdlog/spdlog.h>

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

Recorder::Recorder(fs::path directory, const nlohmann::json& metadata,
                   const Eigen::Isometry3d& initial_map_from_odom, Limits limits)
    : directory_(std::move(directory)), metadata_(metadata), limits_(limits) {
  std::error_code error;
  if (fs::exists(directory_ / kRecordingFile, error) || fs::exists(directory_ / kScansFile, error))
    throw std::runtime_error(directory_.string() +
                             " already holds a recording (record into a new directory)");
  fs::create_directories(directory_ / kScansDirectory, error);
  if (error)
    throw std::runtime_error("cannot create " + (directory_ / kScansDirectory).string() + ": " +
                             error.message());
  metadata_["format"] = kRecordingFormat;
  metadata_["version"] = kRecordingVersion;
  nlohmann::json matrix = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      matrix.push_back(initial_map_from_odom.matrix()(row, col));
  }
  metadata_["initial_map_from_odom"] = std::move(matrix);
  metadata_["started_at"] =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  try {
    write_metadata(false);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("cannot start the recording: ") + e.what());
  }
  scans_csv_ = open_csv(directory_ / kScansFile, scans_csv_header());
  odometry_csv_ = open_csv(directory_ / kOdometryFile, odometry_csv_header());
  thread_ = std::thread([this] { run(); });
}

Recorder::~Recorder() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable())
    thread_.join();
  try {
    write_metadata(true);
  } catch (const std::exception& e) {
    spdlog::error("recording: {}", e.what());
  }
  const RecorderStatus s = status();
  spdlog::info("recording in {}: {} scans, {} odometry samples, {} dropped, {} write errors",
               directory_.string(), s.scans, s.samples, s.dropped, s.errors);
}

void Recorder::record(const RobotSample& sample) {
  {
    std::lock_guard lock(mutex_);
    if (queued_samples_ >= limits_.queued_samples) {
      ++status_.dropped;
      return;
    }
    ++queued_samples_;
    queue_.emplace_back(sample);
  }
  wake_.notify_one();
}

void Recorder::record(const ScanEvent& scan) {
  {
    std::lock_guard lock(mutex_);
    if (queued_scans_ >= limits_.queued_scans) {
      ++status_.dropped;
      if (status_.dropped == 1)
        spdlog::warn("recording: the disk falls behind, dropping (counted in recording.json)");
      return;
    }
    ++queued_scans_;
    queue_.emplace_back(scan);
  }
  wake_.notify_one();
}

void Recorder::flush() {
  std::unique_lock lock(mutex_);
  drained_.wait(lock, [this] { return (queue_.empty() && !writing_) || !thread_.joinable(); });
}

RecorderStatus Recorder::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void Recorder::run() {
  while (true) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) {  // stopping, and everything is written
        drained_.notify_all();
        return;
      }
      item = std::move(queue_.front());
      queue_.pop_front();
      if (std::holds_alternative<ScanEvent>(item))
        --queued_scans_;
      else
        --queued_samples_;
      writing_ = true;
    }
    write(item);
    {
      std::lock_guard lock(mutex_);
      writing_ = false;
      if (queue_.empty())
        drained_.notify_all();
    }
  }
}

void Recorder::write(const Item& item) {
  try {
    if (const auto* sample = std::get_if<RobotSample>(&item)) {
      odometry_csv_ << odometry_csv_row(*sample);
      odometry_csv_.flush();
      if (!odometry_csv_)
        throw std::runtime_error("cannot write " + (directory_ / kOdometryFile).string());
      std::lock_guard lock(mutex_);
      ++status_.samples;
      return;
    }
    const ScanEvent& scan = std::get<ScanEvent>(item);
    // Numbered by attempt, so a failed write never makes a later scan reuse (or fight over) its name.
    const std::string file = scan_file_name(next_scan_file_++);
    // The scan file first, then its row: every listed scan exists.
    write_file_atomically(directory_ / file, io::encode_binary_pcd(scan.points, scan.point_times),
                          Durability::kOrdered);
    scans_csv_ << scans_csv_row(scan, file);
    scans_csv_.flush();
    if (!scans_csv_)
      throw std::runtime_error("cannot write " + (directory_ / kScansFile).string());
    std::lock_guard lock(mutex_);
    ++status_.scans;
  } catch (const std::exception& e) {
    std::size_t errors = 0;
    {
      std::lock_guard lock(mutex_);
      errors = ++status_.errors;
    }
    if (errors <= 10)  // a full disk fails every write: the first few say why
      spdlog::error("recording: {}", e.what());
  }
}

void Recorder::write_metadata(bool finished) {
  nlohmann::json metadata = metadata_;
  const RecorderStatus s = status();
  metadata["finished"] = finished;
  metadata["scans"] = s.scans;
  metadata["samples"] = s.samples;
  metadata["dropped"] = s.dropped;
  metadata["errors"] = s.errors;
  write_file_atomically(directory_ / kRecordingFile, metadata.dump(2) + "\n", Durability::kOrdered);
}

}  // namespace strata::replay

#include "server/pipeline/mapping_worker.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <future>
#include <iterator>
#include <system_error>
#include <utility>

#include "core/files/temporary_files.hpp"
#include "core/mls/map_export.hpp"
#include "core/mls/mls_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::pipeline {
namespace {

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A directory of its own for one download's files, removed with it.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    static std::atomic<unsigned> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("strata-download-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

MappingWorker::MappingWorker(MapState& state, std::filesystem::path maps_dir, MappingOptions options)
    : state_(state), maps_dir_(std::move(maps_dir)), options_(std::move(options)), live_(options_.map) {
  std::filesystem::create_directories(maps_dir_);  // throws with the reason when it cannot
  // A save killed before its rename (power cut, SIGKILL) leaves its temporary behind; nothing ever reads
  // it, so it would only take space. Only files named like our temporaries, of processes that are gone.
  for (const auto& stale : remove_stale_temporaries(maps_dir_))
    spdlog::info("removed {}: left by an interrupted map save", stale.string());
}

MappingWorker::~MappingWorker() {
  stop();
}

void MappingWorker::add_listener(MapUpdateListener listener) {
  listeners_.push_back(std::move(listener));
}

void MappingWorker::start() {
  std::lock_guard lock(mutex_);
  if (running_)
    return;
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void MappingWorker::stop() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable())
    thread_.join();
  // What was still waiting is abandoned: scans are dropped, and a command's waiting caller sees its
  // promise broken (run_on_mapping_thread answers false).
  std::lock_guard lock(mutex_);
  queue_.clear();
  waiting_scans_ = 0;
}

void MappingWorker::submit(ScanEvent scan, const Eigen::Isometry3d& map_from_sensor) {
  submit(preprocess(std::move(scan), options_.min_range), map_from_sensor);
}

void MappingWorker::submit(PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor) {
  {
    std::lock_guard lock(mutex_);
    if (waiting_scans_ >= std::max<std::size_t>(options_.queue_capacity, 1)) {
      const auto oldest = std::find_if(queue_.begin(), queue_.end(),
                                       [](const Item& item) { return std::holds_alternative<Scan>(item); });
      queue_.erase(oldest);
      --waiting_scans_;
      ++status_.dropped;
    }
    queue_.emplace_back(Scan{std::move(scan), map_from_sensor});
    ++waiting_scans_;
  }
  wake_.notify_all();
}

bool MappingWorker::flush() {
  return run_on_mapping_thread([] {});
}

MappingStatus MappingWorker::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void MappingWorker::run() {
  while (true) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return !running_ || !queue_.empty(); });
      if (!running_)
        return;
      item = std::move(queue_.front());
      queue_.pop_front();
      if (std::holds_alternative<Scan>(item))
        --waiting_scans_;
    }
    if (const auto* scan = std::get_if<Scan>(&item))
      map_scan(*scan);
    else
      std::get<Task>(item)();
  }
}

namespace {

double wall_clock_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

void MappingWorker::map_scan(const Scan& scan) {
  const ScanEvent& event = scan.preprocessed.event;
  if (!scan.map_from_sensor.matrix().allFinite() || !event.sensor_to_base.matrix().allFinite()) {
    // A broken pose would put the scan (and the region to refresh) nowhere: drop it, keep the map.
    spdlog::warn("mapping: scan at t={:.1f} not mapped: its pose is not finite", event.stamp);
    return;
  }
  // How long the scan took to get here since it reached the pipeline: the localizer (preprocessing,
  // registration) and this queue. Logged with the mapping's own times: the scan-to-client latency budget.
  const double waited_ms = event.received_at > 0.0 ? (wall_clock_now() - event.received_at) * 1e3 : 0.0;
  const Eigen::Isometry3d map_from_base = scan.map_from_sensor * event.sensor_to_base.inverse();
  const PointCloud points = transformed(scan.preprocessed.points, map_from_base);
  MappingTimes times;
  try {
    times = live_.add_scan(points, scan.map_from_sensor.translation(), map_from_base.translation(),
                           event.received_at);
  } catch (const std::exception& error) {  // an encoder failure must not end the mapping thread
    spdlog::error("mapping: scan at t={:.1f} not mapped: {}", event.stamp, error.what());
    return;
  }
  {
    std::lock_guard lock(mutex_);
    ++status_.scans;
    status_.last = times;
  }
  publish();
  spdlog::debug(
      "mapped scan at t={:.1f}: {} points, {} tiles changed; reached mapping {:.1f} ms after receipt; insert "
      "{:.1f} ms, drivable {:.1f} ms, tiles {:.1f} ms, png {:.1f} ms; published {:.1f} ms after receipt",
      event.stamp, points.size(), times.changed_tiles, waited_ms, times.insert_ms, times.drivable_ms,
      times.tiles_ms, times.png_ms,
      event.received_at > 0.0 ? (wall_clock_now() - event.received_at) * 1e3 : 0.0);
}

void MappingWorker::publish() {
  state_.publish(live_.snapshot());
  if (on_published_)
    on_published_();
  const DrivableMap* drivable = live_.drivable();
  if (drivable == nullptr || !live_.robot_ground())
    return;
  const MapUpdate update{live_.map(), *drivable, *live_.robot_ground(), live_.map().version()};
  for (const MapUpdateListener& listener : listeners_) {
    try {
      listener(update);
    } catch (const std::exception& error) {  // a listener's failure must not end the mapping thread
      spdlog::error("map update listener failed: {}", error.what());
    }
  }
}

bool MappingWorker::run_on_mapping_thread(Task task) const {
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> finished = done->get_future();
  {
    std::lock_guard lock(mutex_);
    if (!running_)
      return false;
    queue_.emplace_back(Task([task = std::move(task), done] {
      task();
      done->set_value();
    }));
  }
  wake_.notify_all();
  try {
    finished.get();
  } catch (const std::future_error&) {  // the worker stopped before it got to the task
    return false;
  }
  return true;
}

CommandResult MappingWorker::save_map(const std::string& name) {
  if (!protocol::is_valid_map_name(name))
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "'" + name + "' is not a map name (1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot)");
  if (temporary_file_owner(name)) {
    // Such a file is not listed, and the next start may remove it as a save's leftover.
    return CommandResult::failure(ErrorCode::kBadParams,
                                  "'" + name + "' is named like a temporary file (NAME.tmp.NUMBER)");
  }
  CommandResult result = CommandResult::failure(ErrorCode::kUnavailable, "the mapping worker is not running");
  run_on_mapping_thread([&] {
    try {
      save_mls_map(live_.map(), maps_dir_ / name);  // atomic: temporary file, fsync, rename
      result = CommandResult::success();
      spdlog::info("map saved to {}", (maps_dir_ / name).string());
    } catch (const std::exception& error) {
      result = CommandResult::failure(ErrorCode::kIoError, error.what());
    }
  });
  return result;
}

CommandResult MappingWorker::load_map(const std::string& name) {
  if (!protocol::is_valid_map_name(name))
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "'" + name + "' is not a map name (1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot)");
  const std::filesystem::path path = maps_dir_ / name;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    return CommandResult::failure(ErrorCode::kNotFound, "no map named '" + name + "'");
  CommandResult result = CommandResult::failure(ErrorCode::kUnavailable, "the mapping worker is not running");
  run_on_mapping_thread([&] {
    MlsMap loaded;
    try {
      loaded = load_mls_map(path);  // the whole file is checked before anything changes
    } catch (const std::exception& failure) {
      result = CommandResult::failure(ErrorCode::kCorruptFile, failure.what());
      return;
    }
    try {
      live_.replace(std::move(loaded));
    } catch (const std::exception& failure) {
      result = CommandResult::failure(ErrorCode::kIoError, failure.what());
      return;
    }
    result = CommandResult::success();
    spdlog::info("map loaded from {}", path.string());
    publish();
  });
  return result;
}

std::vector<MapFileInfo> MappingWorker::list_maps() const {
  std::vector<MapFileInfo> maps;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(maps_dir_, error)) {
    const std::string name = entry.path().filename().string();
    // Hidden files and save_mls_map's temporaries (name.tmp.PID) are not maps.
    if (!protocol::is_valid_map_name(name) || temporary_file_owner(name) || !entry.is_regular_file(error))
      continue;
    MapFileInfo info;
    info.name = name;
    info.bytes = entry.file_size(error);
    const auto modified = std::chrono::file_clock::to_sys(entry.last_write_time(error));
    info.modified = std::chrono::duration<double>(modified.time_since_epoch()).count();
    maps.push_back(std::move(info));
  }
  std::sort(maps.begin(), maps.end(),
            [](const MapFileInfo& a, const MapFileInfo& b) { return a.name < b.name; });
  return maps;
}

std::vector<std::uint8_t> MappingWorker::download(const std::string& format) const {
  if (format != "strata" && format != "ply" && format != "pgm" && format != "yaml")
    return {};
  std::vector<std::uint8_t> bytes;
  run_on_mapping_thread([&] {
    try {
      if (format == "strata" || format == "ply") {
        if (live_.map().patch_count() == 0)
          return;
        if (format == "strata") {
          const std::string data = serialize_mls_map(live_.map());
          bytes.assign(data.begin(), data.end());
          return;
        }
        const ScratchDirectory scratch;
        write_mls_ply(live_.map(), scratch.path() / "map.ply");
        bytes = read_bytes(scratch.path() / "map.ply");
        return;
      }
      const DrivableMap* drivable = live_.drivable();
      if (drivable == nullptr || drivable->grid.cells.empty())
        return;
      const ScratchDirectory scratch;
      const std::filesystem::path pgm = write_ros_map(drivable->grid, scratch.path() / "map.yaml");
      bytes = read_bytes(format == "pgm" ? pgm : scratch.path() / "map.yaml");
    } catch (const std::exception& error) {
      spdlog::error("map download as {} failed: {}", format, error.what());
      bytes.clear();
    }
  });
  return bytes;
}

}  // namespace strata::pipeline

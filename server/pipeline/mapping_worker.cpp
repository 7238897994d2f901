#include "server/pipeline/mapping_worker.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <initializer_list>
#include <iterator>
#include <utility>

#include "server/pipeline/scan_preprocessing.hpp"

namespace strata::pipeline {

MappingWorker::MappingWorker(MapState& state, std::filesystem::path maps_dir, MappingOptions options)
    : state_(state),
      store_(std::move(maps_dir)),
      options_(std::move(options)),
      live_(options_.map),
      rebuilder_(options_.map.mls, options_.rebuild) {}

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

void MappingWorker::submit(PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
                           std::optional<KeyframeAnchor> anchor) {
  {
    std::lock_guard lock(mutex_);
    std::vector<Eigen::Vector3d> passed;
    if (waiting_scans_ >= std::max<std::size_t>(options_.queue_capacity, 1)) {
      const auto is_scan = [](const Item& item) { return std::holds_alternative<Scan>(item); };
      const auto oldest = std::find_if(queue_.begin(), queue_.end(), is_scan);
      // Its points go, where the robot stood stays: the next scan marks the way through it.
      Scan& dropped = std::get<Scan>(*oldest);
      passed = std::move(dropped.passed);
      const Eigen::Isometry3d map_from_base =
          dropped.map_from_sensor * dropped.preprocessed.event.sensor_to_base.inverse();
      if (map_from_base.matrix().allFinite())
        passed.push_back(map_from_base.translation());
      const auto next = std::find_if(std::next(oldest), queue_.end(), is_scan);
      if (next != queue_.end()) {
        std::vector<Eigen::Vector3d>& later = std::get<Scan>(*next).passed;
        later.insert(later.begin(), passed.begin(), passed.end());
        passed.clear();
      }
      queue_.erase(oldest);
      --waiting_scans_;
      ++status_.dropped;
    }
    queue_.emplace_back(Scan{std::move(scan), map_from_sensor, std::move(passed), std::move(anchor)});
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
      if (queue_.empty() && running_) {
        // Nothing waits: refresh what a burst left pending (its last scan may not have been mapped, or
        // the scans behind it were dropped) before sleeping, so no inserted scan waits on the next one.
        lock.unlock();
        MappingTimes times;
        refresh_pending(times);
        lock.lock();
      }
      wake_.wait(lock, [this] { return !running_ || !queue_.empty(); });
      if (!running_)
        return;
      item = std::move(queue_.front());
      queue_.pop_front();
      if (std::holds_alternative<Scan>(item))
        --waiting_scans_;
    }
    if (const auto* scan = std::get_if<Scan>(&item)) {
      map_scan(*scan);
    } else {
      MappingTimes times;
      refresh_pending(times);  // a task (a save, a download, a flush) sees every scan mapped before it
      std::get<Task>(item)();
    }
  }
}

namespace {

double wall_clock_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

bool MappingWorker::insert(const Scan& scan, MappingTimes& times) {
  const ScanEvent& event = scan.preprocessed.event;
  if (!scan.map_from_sensor.matrix().allFinite() || !event.sensor_to_base.matrix().allFinite()) {
    // A broken pose would put the scan (and the region to refresh) nowhere: drop it, keep the map.
    spdlog::warn("mapping: scan at t={:.1f} not mapped: its pose is not finite", event.stamp);
    return false;
  }
  const Eigen::Isometry3d map_from_base = scan.map_from_sensor * event.sensor_to_base.inverse();
  const PointCloud points = transformed(scan.preprocessed.points, map_from_base);
  try {
    for (const Eigen::Vector3d& ground : scan.passed)
      live_.mark_passed(ground);
    times = live_.insert_scan(points, scan.map_from_sensor.translation(), map_from_base.translation(),
                              event.received_at);
  } catch (const std::exception& error) {  // an encoder failure must not end the mapping thread
    spdlog::error("mapping: scan at t={:.1f} not mapped: {}", event.stamp, error.what());
    return false;
  }
  live_.set_saved_version({});  // the map is no stored version any more
  return true;
}

bool MappingWorker::refresh_pending(MappingTimes& times) {
  try {
    if (!live_.refresh_pending(times))
      return false;
  } catch (const std::exception& error) {  // an encoder failure must not end the mapping thread
    spdlog::error("mapping: the map not refreshed: {}", error.what());
    return false;
  }
  last_refresh_ = std::chrono::steady_clock::now();
  {
    std::lock_guard lock(mutex_);
    status_.last = times;
  }
  publish();
  return true;
}

void MappingWorker::map_scan(const Scan& scan) {
  const ScanEvent& event = scan.preprocessed.event;
  // How long the scan took to get here since it reached the pipeline: the localizer (preprocessing,
  // registration) and this queue. Logged with the mapping's own times: the scan-to-client latency budget.
  const double waited_ms = event.received_at > 0.0 ? (wall_clock_now() - event.received_at) * 1e3 : 0.0;
  MappingTimes times;
  if (mode_ == MapMode::kLocalize) {
    // The loaded map is fixed: the scan only says where the robot is, and so which level is drivable.
    const Eigen::Isometry3d map_from_base = scan.map_from_sensor * event.sensor_to_base.inverse();
    if (map_from_base.matrix().allFinite() && live_.follow_robot(map_from_base.translation()))
      publish();
    return;
  }
  if (!insert(scan, times))
    return;
  if (recording_)
    mapped_meanwhile_.push_back(scan);
  recent_.push_back(scan);
  if (recent_.size() > kRecentScans)
    recent_.pop_front();
  bool more_waiting = false;
  {
    std::lock_guard lock(mutex_);
    ++status_.scans;
    more_waiting = waiting_scans_ > 0;
  }
  // Behind a burst, the next scans first and one refresh for all of them; but never an older drivable map
  // and tiles than max_refresh_delay.
  if (more_waiting && last_refresh_ &&
      std::chrono::steady_clock::now() - *last_refresh_ < options_.max_refresh_delay)
    return;
  if (!refresh_pending(times))
    return;
  spdlog::debug(
      "mapped scan at t={:.1f}: {} points, {} tiles changed; reached mapping {:.1f} ms after receipt; insert "
      "{:.1f} ms, drivable {:.1f} ms, tiles {:.1f} ms, png {:.1f} ms; published {:.1f} ms after receipt",
      event.stamp, scan.preprocessed.points.size(), times.changed_tiles, waited_ms, times.insert_ms,
      times.drivable_ms, times.tiles_ms, times.png_ms,
      event.received_at > 0.0 ? (wall_clock_now() - event.received_at) * 1e3 : 0.0);
}

bool MappingWorker::rebuild_from(const std::vector<KeyframePose>& keyframes) {
  std::lock_guard rebuild_lock(rebuild_mutex_);
  const KeyframeMoves moves = rebuilder_.moves(keyframes);
  if (moves.moved == 0)
    return false;
  bool loaded = false;
  std::vector<Scan> after_keyframes;  // mapped before the rebuild started, newer than the newest keyframe
  const double newest_keyframe = keyframes.empty() ? 0.0 : keyframes.back().keyframe->stamp;
  const bool running = run_on_mapping_thread([&] {
    loaded = loaded_;
    recording_ = !loaded_;
    mapped_meanwhile_.clear();
    for (const Scan& scan : recent_) {
      if (scan.preprocessed.event.stamp > newest_keyframe)
        after_keyframes.push_back(scan);
    }
  });
  if (!running || loaded)
    return false;

  const auto start = std::chrono::steady_clock::now();
  MlsMap map = rebuilder_.build(keyframes);
  const double build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  bool swapped = false;
  std::size_t again = 0;
  run_on_mapping_thread([&] {
    recording_ = false;
    const std::vector<Scan> meanwhile = std::exchange(mapped_meanwhile_, {});
    if (loaded_)  // a map was loaded while this one was built: it wins
      return;
    try {
      live_.replace(std::move(map), LiveMap::Replacement::kRebuilt);
      live_.set_saved_version({});
    } catch (const std::exception& error) {  // an encoder failure: the old map stays
      spdlog::error("mapping: the rebuilt map could not replace the live map: {}", error.what());
      return;
    }
    // The scans no keyframe holds: those mapped after the newest keyframe, before the rebuild started
    // and while the keyframes were being put in; they went into the map just replaced. Moved as the
    // keyframe they came after moved: at the poses they were mapped with, they stayed where the loop
    // closure moved the map from.
    for (const std::vector<Scan>* scans :
         std::initializer_list<const std::vector<Scan>*>{&after_keyframes, &meanwhile}) {
      for (const Scan& scan : *scans) {
        MappingTimes times;
        again += insert(moved_with_keyframe(scan, keyframes), times) ? 1 : 0;
      }
    }
    swapped = true;
    {
      std::lock_guard lock(mutex_);
      ++status_.rebuilds;
    }
    MappingTimes times;
    try {
      live_.refresh_pending(times);
    } catch (const std::exception& error) {
      spdlog::error("mapping: the rebuilt map not refreshed: {}", error.what());
    }
    publish();
  });
  if (!swapped)
    return false;
  rebuilder_.landed(keyframes);
  spdlog::info(
      "mapping: map rebuilt from {} keyframes after the pose graph moved {} of them (up to {:.2f} m); built "
      "in "
      "{:.2f} s, {} scans newer than the keyframes mapped again",
      moves.keyframes, moves.moved, moves.largest_shift, build_seconds, again);
  return true;
}

MappingWorker::Scan MappingWorker::moved_with_keyframe(const Scan& scan,
                                                       const std::vector<KeyframePose>& keyframes) {
  if (!scan.anchor)
    return scan;
  // The scans to move came after the newest keyframes: look from the back.
  const auto found = std::find_if(keyframes.rbegin(), keyframes.rend(), [&](const KeyframePose& keyframe) {
    return keyframe.keyframe == scan.anchor->keyframe;
  });
  if (found == keyframes.rend())
    return scan;
  const Eigen::Isometry3d moved = found->pose * scan.anchor->pose.inverse();
  Scan out = scan;
  out.map_from_sensor = moved * scan.map_from_sensor;
  for (Eigen::Vector3d& ground : out.passed)
    ground = moved * ground;
  return out;
}

void MappingWorker::publish() {
  // The listeners first (the navigator's planning surfaces among them): once the status shows a map
  // version, a goal set against it must find that map, not race its planning copy.
  notify_listeners();
  state_.publish(live_.snapshot());
  if (on_published_)
    on_published_();
}

void MappingWorker::notify_listeners() {
  const DrivableMap* drivable = live_.drivable();
  if (drivable == nullptr || !live_.robot_ground())
    return;
  const MapUpdate update{live_.map(), *drivable, *live_.robot_ground(), live_.map().version(),
                         [this] { return live_.whole_level(std::nullopt).drivable; }};
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
  if (CommandResult checked = MapStore::check_name(name); !checked.ok)
    return checked;
  CommandResult result = CommandResult::failure(ErrorCode::kUnavailable, "the mapping worker is not running");
  run_on_mapping_thread([&] {
    const std::shared_ptr<const LocalizationMap> localization = localization_to_keep();
    std::string version;
    result = store_.save(live_.map(), localization.get(), name, &version);
    if (result.ok) {
      live_.set_name(name);
      live_.set_saved_version(version);
      // The snapshot names the map and its version at once (the map itself is as it was: no listeners).
      live_.rename_snapshot();
      state_.publish(live_.snapshot());
      if (on_published_)
        on_published_();
    }
  });
  return result;
}

std::shared_ptr<const LocalizationMap> MappingWorker::localization_to_keep() const {
  // The map was loaded: the localization map it came with (this run's keyframes are not in its frame).
  // Otherwise the pose graph's keyframes as they are now, which the map follows.
  if (loaded_ || !keyframe_source_)
    return loaded_localization_;
  const std::vector<KeyframePose> keyframes = keyframe_source_();
  if (keyframes.empty())
    return loaded_localization_;
  return std::make_shared<const LocalizationMap>(make_localization_map(keyframes));
}

CommandResult MappingWorker::load_map(const std::string& name, MapMode mode) {
  // Read and checked here, on the caller's thread: the mapping goes on meanwhile, and a corrupt file
  // changes nothing.
  return take_up(store_.load(name), name, mode);
}

CommandResult MappingWorker::load_map_version(const std::string& name, const std::string& version,
                                              MapMode mode) {
  return take_up(store_.load_version(name, version), name, mode);
}

std::vector<MapVersionInfo> MappingWorker::list_map_versions() const {
  return store_.versions().list();
}

MapVersionFile MappingWorker::read_map_version(const std::string& name, const std::string& version) const {
  return store_.versions().read(name, version);
}

CommandResult MappingWorker::add_map_version(const std::string& name, const std::string& version,
                                             std::string_view bytes, std::string_view sha256) {
  return store_.add_version(name, version, bytes, sha256);  // the caller's thread: the map is not touched
}

CommandResult MappingWorker::delete_map_version(const std::string& name, const std::string& version) {
  CommandResult result = CommandResult::failure(ErrorCode::kUnavailable, "the mapping worker is not running");
  // On the mapping thread: no load of the same version between the check and the removal.
  run_on_mapping_thread([&] {
    if (live_.name() == name && live_.saved_version() == version) {
      result = CommandResult::failure(ErrorCode::kBadParams,
                                      "version " + version + " of map " + name + " is in use");
      return;
    }
    result = store_.versions().remove(name, version)
                 ? CommandResult::success()
                 : CommandResult::failure(ErrorCode::kNotFound, "no version " + version.substr(0, 64) +
                                                                    " of map " + name.substr(0, 64));
  });
  return result;
}

CommandResult MappingWorker::take_up(MapStore::Loaded loaded, const std::string& name, MapMode mode) {
  if (!loaded.result.ok)
    return loaded.result;
  const bool localizable = loaded.localization && !loaded.localization->empty();
  if (mode == MapMode::kLocalize && !localizable) {
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "the map '" + name +
            "' has no localization data (saved by an older Strata or without the pose graph): it can be "
            "loaded for mapping (viewing), not for localizing");
  }
  std::shared_ptr<const LocalizationMap> localization =
      localizable ? std::make_shared<const LocalizationMap>(std::move(*loaded.localization)) : nullptr;
  CommandResult result = CommandResult::failure(ErrorCode::kUnavailable, "the mapping worker is not running");
  run_on_mapping_thread([&] {
    const std::string previous_name = live_.name();
    const std::string previous_version = live_.saved_version();
    try {
      live_.set_localizing(mode == MapMode::kLocalize);  // before: the new map's snapshot says it
      live_.set_name(name);
      live_.set_saved_version(loaded.version);
      live_.replace(std::move(loaded.map), LiveMap::Replacement::kLoaded);
      loaded_ = true;
    } catch (const std::exception& failure) {
      live_.set_localizing(mode_ == MapMode::kLocalize);
      live_.set_name(previous_name);
      live_.set_saved_version(previous_version);
      result = CommandResult::failure(
          ErrorCode::kIoError,
          std::string("the map could not be taken up, the live map is unchanged: ") + failure.what());
      return;
    }
    mode_ = mode;
    loaded_localization_ = localization;
    if (localization_sink_)
      localization_sink_(mode == MapMode::kLocalize ? localization : nullptr);
    result = CommandResult::success();
    if (mode == MapMode::kLocalize) {
      result.message = "localizing in the map; it is not changed";
    } else if (!localizable) {
      result.message =
          "loaded for viewing and mapping only: the file has no localization data (saved by an older "
          "Strata or without the pose graph), so it cannot be localized in";
    } else {
      result.message = "mapping on in the loaded map";
    }
    spdlog::info("map loaded from {}{} ({}): {}", (store_.directory() / name).string(),
                 loaded.version.empty() ? std::string() : ", version " + loaded.version, to_string(mode),
                 result.message);
    publish();
  });
  return result;
}

std::vector<Eigen::Isometry3d> MappingWorker::trajectory() const {
  // A loaded map's keyframes (this run's are not in its frame), or the pose graph's as they are now.
  if (loaded_)
    return loaded_localization_ ? loaded_localization_->keyframe_poses : std::vector<Eigen::Isometry3d>();
  std::vector<Eigen::Isometry3d> poses;
  if (keyframe_source_) {
    for (const KeyframePose& keyframe : keyframe_source_())
      poses.push_back(keyframe.pose);
  }
  return poses;
}

std::vector<MapFileInfo> MappingWorker::list_maps() const {
  return store_.list();
}

MapDownload MappingWorker::download(const std::string& format, std::optional<std::uint64_t> version) const {
  MapDownload result;
  run_on_mapping_thread([&] {
    const std::uint64_t map_version = live_.map().version();
    if (last_download_ && last_download_->format == format && last_download_->asked == version &&
        last_download_->map_version == map_version) {
      result = last_download_->download;
      result.reused = true;
      return;
    }
    try {
      result.version = map_version;
      const bool mcap = MapStore::is_mcap(format);
      if (format != "pgm" && format != "yaml" && !mcap) {
        const std::shared_ptr<const LocalizationMap> localization =
            format == "strata" ? localization_to_keep() : nullptr;
        result.bytes = MapStore::download(format, live_.map(), localization.get(), nullptr, result.version);
      } else {
        // The drivable map over the whole map, of the version asked for. An MCAP file holds the patches
        // and the keyframes too, so it is made before the robot has a place, without the drivable map.
        const LiveMap::WholeLevel level = live_.whole_level(version);
        result.version_gone = level.gone;
        if (level.drivable || (mcap && !level.gone)) {
          result.version = level.drivable ? level.version : map_version;
          result.bytes =
              MapStore::download(format, live_.map(), nullptr, level.drivable.get(), result.version,
                                 mcap ? trajectory() : std::vector<Eigen::Isometry3d>());
        }
      }
      if (!result.bytes.empty())
        last_download_ = LastDownload{format, version, map_version, result};
    } catch (const std::exception& error) {
      spdlog::error("map download as {} failed: {}", format, error.what());
      result.bytes.clear();
    }
  });
  return result;
}

}  // namespace strata::pipeline

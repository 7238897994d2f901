#pragma once

#include <Eigen/Geometry>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "core/localization/keyframe.hpp"
#include "core/localization/localization_map.hpp"
#include "drivers/scan_event.hpp"
#include "server/control/robot_commands.hpp"
#include "server/pipeline/live_map.hpp"
#include "server/pipeline/map_rebuilder.hpp"
#include "server/pipeline/map_store.hpp"
#include "server/pipeline/map_update.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "server/state/map_state.hpp"

namespace strata::pipeline {

struct MappingOptions {
  LiveMapOptions map;
  /// Registered scans waiting to be mapped; when full the oldest waiting scan is dropped (counted), so the
  /// localizer never waits for the mapping.
  std::size_t queue_capacity = 4;
  /// Returns nearer the sensor than this are the robot itself (as for registration), metres: for scans
  /// submitted unprocessed (the live pipeline's come preprocessed by the localizer, with the same bound).
  double min_range = 0.3;
  /// Scans waiting behind one another are inserted first and refreshed together (the drivable map, the
  /// tiles, the snapshot: LiveMap::refresh_pending), but never this long after the last refresh.
  std::chrono::milliseconds max_refresh_delay{250};
  MapRebuildOptions rebuild;
};

/// What the mapping worker has done, for status and tests.
struct MappingStatus {
  std::size_t scans = 0;     ///< mapped
  std::size_t dropped = 0;   ///< dropped from a full queue
  std::size_t rebuilds = 0;  ///< maps rebuilt from keyframes the pose graph moved
  MappingTimes last;
};

/// The pipeline worker for the map (docs/architecture.md 3, steps 6-8) on its own thread: inserts each
/// registered scan at full resolution into the live map, recomputes the drivable map at the robot's level
/// for the changed region, re-encodes the changed tiles and the occupancy image, publishes the snapshot
/// into MapState, then tells the listeners. Map commands (save, load, list, download) run on the same
/// thread, in order with the scans, so they see the map between two scans, never during one; the files
/// and formats are the MapStore's.
class MappingWorker final : public MapCommands {
 public:
  /// `maps_dir` holds saved maps (a MapStore: created if missing, temporaries of interrupted saves removed).
  MappingWorker(MapState& state, std::filesystem::path maps_dir, MappingOptions options = {});
  ~MappingWorker() override;
  MappingWorker(const MappingWorker&) = delete;
  MappingWorker& operator=(const MappingWorker&) = delete;

  /// Listeners are added before start(); they run on the mapping thread after every map change.
  void add_listener(MapUpdateListener listener);
  /// Set before start(): called on the mapping thread right after each new snapshot is in MapState (every
  /// mapped scan, every load), so the network side can send it at once instead of polling for it. Must
  /// return at once (post to an executor).
  void on_published(std::function<void()> callback) { on_published_ = std::move(callback); }
  /// Set before start(): what a saved map keeps for localizing in it, asked for at each save (the pose
  /// graph's keyframes at their current poses). Without it maps are saved without.
  void set_keyframe_source(std::function<std::vector<KeyframePose>()> source) {
    keyframe_source_ = std::move(source);
  }
  /// Set before start(): called on the mapping thread when a map is loaded, with what to localize in (a map
  /// loaded for localizing) or null (for mapping): the localizer follows.
  using LocalizationMapSink = std::function<void(std::shared_ptr<const LocalizationMap> map)>;
  void on_map_loaded(LocalizationMapSink sink) { localization_sink_ = std::move(sink); }
  void start();
  /// Finishes the scan or command under way, abandons waiting scans, fails waiting commands.
  void stop();

  /// A registered scan, preprocessed by the localizer (step 1), and where its sensor was in the map frame;
  /// `anchor` the keyframe it came after, which a rebuild moves it with. Returns at once.
  void submit(PreprocessedScan scan, const Eigen::Isometry3d& map_from_sensor,
              std::optional<KeyframeAnchor> anchor = std::nullopt);
  /// The same for a scan as the driver took it (sensor frame): preprocessed here with
  /// MappingOptions::min_range (tests, tools), and mapped as measured: deskewing needs the motion, which
  /// the localizer knows and this worker does not.
  void submit(ScanEvent scan, const Eigen::Isometry3d& map_from_sensor);
  /// The pose graph moved keyframes (docs/architecture.md 4.1, "the map follows"): when any moved from
  /// where the map has them, builds the map anew from them on the caller's thread (mapping goes on
  /// meanwhile and the old map stays served), then swaps it in on the mapping thread and maps again the
  /// scans newer than the newest keyframe (mapped before the rebuild or in the meantime), moved as the
  /// keyframe they came after moved. Does nothing after a map was loaded: the keyframes do not hold it.
  /// True when the map was rebuilt.
  bool rebuild_from(const std::vector<KeyframePose>& keyframes);
  /// Waits until everything submitted before is done (tests, tools, a replay as fast as possible). False
  /// when the worker is not running.
  bool flush();
  [[nodiscard]] MappingStatus status() const;

  CommandResult save_map(const std::string& name) override;
  CommandResult load_map(const std::string& name, MapMode mode) override;
  [[nodiscard]] std::vector<MapFileInfo> list_maps() const override;
  [[nodiscard]] MapDownload download(const std::string& format,
                                     std::optional<std::uint64_t> version) const override;
  [[nodiscard]] std::vector<MapVersionInfo> list_map_versions() const override;
  [[nodiscard]] MapVersionFile read_map_version(const std::string& name,
                                                const std::string& version) const override;
  CommandResult add_map_version(const std::string& name, const std::string& version, std::string_view bytes,
                                std::string_view sha256) override;
  CommandResult load_map_version(const std::string& name, const std::string& version, MapMode mode) override;
  CommandResult delete_map_version(const std::string& name, const std::string& version) override;

  [[nodiscard]] const std::filesystem::path& maps_dir() const { return store_.directory(); }

 private:
  struct Scan {
    PreprocessedScan preprocessed;
    Eigen::Isometry3d map_from_sensor;
    /// Where the robot stood at the scans dropped from the queue just before this one, oldest first: the
    /// way it drove is marked through them (LiveMap::mark_passed).
    std::vector<Eigen::Vector3d> passed;
    std::optional<KeyframeAnchor> anchor;
  };
  /// `scan` where the rebuild's `keyframes` put the keyframe it came after; as it was when that keyframe is
  /// not among them (none, or one made after the rebuild started, in the frame the rebuild left).
  static Scan moved_with_keyframe(const Scan& scan, const std::vector<KeyframePose>& keyframes);
  using Task = std::function<void()>;
  using Item = std::variant<Scan, Task>;

  void run();
  /// load_map's and load_map_version's common part: a map read and checked becomes the live map.
  CommandResult take_up(MapStore::Loaded loaded, const std::string& name, MapMode mode);
  void map_scan(const Scan& scan);
  /// Steps 6-8 for one scan, without publishing. False when the scan could not be mapped.
  bool insert(const Scan& scan, MappingTimes& times);
  /// Mapping thread: the localization map a save or a native download keeps with the map.
  [[nodiscard]] std::shared_ptr<const LocalizationMap> localization_to_keep() const;
  /// Mapping thread: refreshes and publishes what scans inserted since the last refresh, if anything; false
  /// when nothing was pending or the refresh failed. `times` gets the refresh's times.
  bool refresh_pending(MappingTimes& times);
  /// Mapping thread: the map listeners, then the status and tiles (so a client never sees a version the
  /// listeners have not).
  void publish();
  void notify_listeners();
  /// Mapping thread: where the robot that made the map drove (keyframe poses, oldest first).
  [[nodiscard]] std::vector<Eigen::Isometry3d> trajectory() const;
  /// Runs `task` on the mapping thread and waits for it; false when the worker is not running.
  bool run_on_mapping_thread(Task task) const;

  MapState& state_;
  MapStore store_;
  MappingOptions options_;
  LiveMap live_;                      // mapping thread only
  bool loaded_ = false;               // mapping thread only: a map file replaced the live map
  MapMode mode_ = MapMode::kMapping;  // mapping thread only
  /// Mapping thread only: the loaded file's localization map, saved again with the map it came with.
  std::shared_ptr<const LocalizationMap> loaded_localization_;
  bool recording_ = false;              // mapping thread only: a rebuild is under way...
  std::vector<Scan> mapped_meanwhile_;  // ...and these scans were mapped since it started
  /// Mapping thread only: the last scans mapped (at most kRecentScans). A rebuild maps again those newer
  /// than its newest keyframe: no keyframe holds them yet, and the newest is where the robot stands.
  std::deque<Scan> recent_;
  static constexpr std::size_t kRecentScans = 30;  // 3 s of a 10 Hz lidar, a keyframe's 1 m and more
  std::mutex rebuild_mutex_;                       // one rebuild at a time; guards rebuilder_
  MapRebuilder rebuilder_;
  std::vector<MapUpdateListener> listeners_;
  std::function<void()> on_published_;
  std::function<std::vector<KeyframePose>()> keyframe_source_;
  LocalizationMapSink localization_sink_;

  mutable std::mutex mutex_;
  mutable std::condition_variable wake_;
  mutable std::deque<Item> queue_;
  std::size_t waiting_scans_ = 0;
  /// Mapping thread only: when the map was last refreshed (MappingOptions::max_refresh_delay); none before
  /// the first refresh. Not the clock's epoch: steady_clock counts from boot, and on a machine up for less
  /// than the delay the first scans behind one another were never refreshed until the last.
  std::optional<std::chrono::steady_clock::time_point> last_refresh_;
  MappingStatus status_;
  bool running_ = false;
  std::thread thread_;
  /// The last download made (mapping thread only), answered again while the map has not changed: clients
  /// fetching the same export at once cost one encoding (issue 59 item 10). One kept, the newest.
  struct LastDownload {
    std::string format;
    std::optional<std::uint64_t> asked;  // the version the request named
    std::uint64_t map_version = 0;       // of the live map it was made from
    MapDownload download;
  };
  mutable std::optional<LastDownload> last_download_;
};

}  // namespace strata::pipeline

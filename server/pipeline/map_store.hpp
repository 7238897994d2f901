#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/localization/localization_map.hpp"
#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"
#include "server/control/robot_commands.hpp"

namespace strata::pipeline {

/// The saved maps of one directory, and the map's download formats as bytes: everything about map files,
/// so the mapping worker is only a queue and a thread. Names follow protocol::is_valid_map_name, the one
/// rule the API checks too: every listed map can be loaded by its name.
class MapStore {
 public:
  /// Creates `directory` if missing (throws with the reason when it cannot) and removes temporaries left
  /// there by interrupted saves.
  explicit MapStore(std::filesystem::path directory);

  /// Whether `name` can be saved as: success, or kBadParams saying why not.
  [[nodiscard]] static CommandResult check_name(const std::string& name);
  /// Saves `map` as `name` atomically (the previous file survives a failure), with what localizing in it
  /// needs when there is that (`localization` may be null); kIoError with the reason.
  [[nodiscard]] CommandResult save(const MlsMap& map, const LocalizationMap* localization,
                                   const std::string& name) const;

  /// A map read from the store: `map` is set only when `result` is a success.
  struct Loaded {
    CommandResult result;
    MlsMap map;
    std::optional<LocalizationMap> localization;  ///< none in older files (view only)
  };
  /// Reads and checks the whole file; kNotFound or kCorruptFile (with the decoder's reason) otherwise.
  [[nodiscard]] Loaded load(const std::string& name) const;
  /// The saved maps by name; hidden files, temporaries and names the API would refuse are not maps.
  [[nodiscard]] std::vector<MapFileInfo> list() const;

  /// `map` in a download format: "strata" (the native file, as save() writes it with `localization`),
  /// "ply", the drivable map as ROS "pgm" or "yaml" (which names map version `version` and how to fetch its
  /// image), or "mcap" / "mcap-uncompressed" (ROS 2 messages, drivers/ros2/map_messages.hpp: the patches,
  /// the drivable map if there is one, the keyframes' `trajectory`; zstd-compressed chunks or plain ones).
  /// Empty for an unknown format or when there is nothing to download (no patches, no drivable map).
  [[nodiscard]] static std::vector<std::uint8_t> download(const std::string& format, const MlsMap& map,
                                                          const LocalizationMap* localization,
                                                          const DrivableMap* drivable, std::uint64_t version,
                                                          std::span<const Eigen::Isometry3d> trajectory = {});
  /// Whether `format` is one of download()'s MCAP formats.
  [[nodiscard]] static bool is_mcap(const std::string& format);

  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }

 private:
  /// A file error's message as clients get it: no absolute paths, no process id (docs/architecture.md 6).
  [[nodiscard]] std::string for_clients(std::string message) const;

  std::filesystem::path directory_;
};

}  // namespace strata::pipeline

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
#include "server/pipeline/map_versions.hpp"

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
  /// needs when there is that (`localization` may be null); kIoError with the reason. Every save is also
  /// an immutable map version (versions()): a new number, or the version with the same bytes if there is
  /// one; `version` (if not null) gets it.
  [[nodiscard]] CommandResult save(const MlsMap& map, const LocalizationMap* localization,
                                   const std::string& name, std::string* version = nullptr) const;

  /// A map read from the store: `map` is set only when `result` is a success.
  struct Loaded {
    CommandResult result;
    MlsMap map;
    std::optional<LocalizationMap> localization;  ///< none in older files (view only)
    std::string version;                          ///< the stored version with these bytes; empty: none
  };
  /// Reads and checks the whole file; kNotFound or kCorruptFile (with the decoder's reason) otherwise.
  [[nodiscard]] Loaded load(const std::string& name) const;
  /// The same for a stored version of a map.
  [[nodiscard]] Loaded load_version(const std::string& name, const std::string& version) const;
  /// Stores `bytes` as a new version, DISABLED (MapCommands::add_map_version).
  [[nodiscard]] CommandResult add_version(const std::string& name, const std::string& version,
                                          std::string_view bytes, std::string_view sha256) const;
  [[nodiscard]] const MapVersions& versions() const { return versions_; }
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
  /// Decodes a whole file read from `path` (a regular file, never a link), a file of map `name`, `label`
  /// naming it to clients.
  [[nodiscard]] Loaded load_file(const std::filesystem::path& path, const std::string& name,
                                 const std::string& label) const;

  std::filesystem::path directory_;
  MapVersions versions_;
};

}  // namespace strata::pipeline

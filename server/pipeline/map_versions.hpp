#pragma once

#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/control/robot_commands.hpp"

namespace strata::pipeline {

/// The map server's immutable map versions (docs/fleet.md, "The map server"), kept below the maps
/// directory in `.versions/<name>/`: `<version>.map` the file, `<version>.meta` its SHA-256, size and the
/// heights its robot drove at (JSON). Both written atomically, the meta first: a version is there once its
/// file is, and then never written again. Hidden from the saved maps' listing (a dot directory).
class MapVersions {
 public:
  /// `maps_dir`: the map store's directory. Removes temporaries of interrupted writes.
  explicit MapVersions(const std::filesystem::path& maps_dir);

  /// Whether `version` can name a version: the map names' rule (A-Z a-z 0-9 . _ -, 1-64, no leading dot).
  [[nodiscard]] static bool is_valid_version(std::string_view version);

  [[nodiscard]] std::vector<MapVersionInfo> list() const;
  [[nodiscard]] std::optional<MapVersionInfo> find(const std::string& name, const std::string& version) const;
  /// The version of `name` whose file has hash `sha256`, if any (the newest of equal ones).
  [[nodiscard]] std::optional<MapVersionInfo> find_by_hash(const std::string& name,
                                                           const std::string& sha256) const;
  /// The next number a save of `name` takes: 1 + the largest whole-number version (1 for none).
  [[nodiscard]] std::string next_number(const std::string& name) const;
  /// Writes `bytes` (with `info`'s hash and heights) as a new version; throws FileWriteError, or
  /// std::runtime_error when the version is there already (versions are never replaced).
  void add(const MapVersionInfo& info, std::string_view bytes) const;
  /// The file's bytes; kNotFound or kIoError.
  [[nodiscard]] MapVersionFile read(const std::string& name, const std::string& version) const;
  /// Removes a version; false when it is not there.
  bool remove(const std::string& name, const std::string& version) const;
  /// Where a version's file is (valid names only).
  [[nodiscard]] std::filesystem::path file_of(const std::string& name, const std::string& version) const;

 private:
  [[nodiscard]] std::filesystem::path meta_of(const std::string& name, const std::string& version) const;
  [[nodiscard]] std::vector<MapVersionInfo> versions_of(const std::filesystem::path& name_dir) const;

  std::filesystem::path root_;
  /// add's check that a version is new and its write are one step: a save (the mapping thread) and a
  /// downloadMap (the fleet's map thread) may add the same version at once; the second is refused.
  mutable std::mutex writing_;
};

}  // namespace strata::pipeline

#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/localization/localization_map.hpp"
#include "core/mls/mls_map.hpp"

namespace strata {

/// A native map file that cannot be written or read; what() says which file and what is wrong with it.
struct MlsFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A native map file's contents.
struct MapFile {
  MlsMap map;
  /// What localizing in the map needs (format 3 on, and only a map made with the pose graph has it):
  /// without it the map can be viewed and planned on, not localized in.
  std::optional<LocalizationMap> localization;
  std::uint32_t format_version = 0;
};

/// The largest map a file may hold, in cells of its bounding box: the drivable map and the surface grid
/// are dense over it, about 40 bytes a cell (a file of 310 KB whose one tile lay 150 tiles from the
/// rest, 23 million cells, took 0.94 GB to load). 25 million is 500 m by 500 m at 0.1 m cells, about
/// 1 GB. A file beyond it is refused before anything is built from it.
inline constexpr std::uint64_t kMaxMapFileCells = 25'000'000;

/// The format version this build writes.
[[nodiscard]] std::uint32_t map_file_format_version();

/// Saves `map` in Strata's native format (little-endian: magic "STRATMLS", format version, total size,
/// the map's config, tile size and version, then per tile its index, version, patch counts per cell and
/// patches; then whether a localization map follows and if so its voxel, keyframe poses and points; last
/// an FNV-1a 64 checksum of everything before it). Atomic: written to a temporary file in the same
/// directory, fsync'ed, then renamed over `path`, so a crash leaves the old file or the new one, never
/// half.
void save_mls_map(const MlsMap& map, const std::filesystem::path& path);
void save_map_file(const MlsMap& map, const LocalizationMap* localization, const std::filesystem::path& path);

/// The bytes save_mls_map writes (for a download without a file).
[[nodiscard]] std::string serialize_mls_map(const MlsMap& map);
[[nodiscard]] std::string serialize_map_file(const MlsMap& map, const LocalizationMap* localization);

/// Decodes the bytes of a native map file (as serialize_mls_map writes them); `source` names them in error
/// messages. Throws MlsFileError as load_mls_map does.
[[nodiscard]] MlsMap deserialize_mls_map(std::string_view data, const std::string& source);
[[nodiscard]] MapFile deserialize_map_file(std::string_view data, const std::string& source);

/// Loads a native map file. Throws MlsFileError on a missing, truncated, corrupted or foreign file.
[[nodiscard]] MlsMap load_mls_map(const std::filesystem::path& path);
[[nodiscard]] MapFile load_map_file(const std::filesystem::path& path);

/// Loads into `map` only if the whole file is valid; on error `map` is untouched and MlsFileError thrown.
void load_mls_map_into(const std::filesystem::path& path, MlsMap& map);

}  // namespace strata

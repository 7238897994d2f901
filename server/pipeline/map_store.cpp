#include "server/pipeline/map_store.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <string_view>
#include <system_error>

#include "core/files/atomic_file.hpp"
#include "core/files/temporary_files.hpp"
#include "core/mls/map_export.hpp"
#include "core/mls/mls_file.hpp"
#include "drivers/ros2/map_messages.hpp"
#include "server/pipeline/file_bytes.hpp"
#include "server/pipeline/file_hash.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::pipeline {

namespace {

/// Where the robot that made the map drove, as heights 0.25 m apart: what a fleet's levels come from.
std::vector<double> keyframe_heights(const LocalizationMap* localization) {
  std::set<double> heights;
  if (localization != nullptr) {
    for (const auto& pose : localization->keyframe_poses)
      heights.insert(std::round(pose.translation().z() * 4.0) / 4.0);
  }
  return {heights.begin(), heights.end()};
}

}  // namespace

MapStore::MapStore(std::filesystem::path directory)
    : directory_((std::filesystem::create_directories(directory), std::move(directory))),
      versions_(directory_) {
  // A save killed before its rename (power cut, SIGKILL) leaves its temporary behind; nothing ever reads
  // it, so it would only take space. Only files named like our temporaries, of processes that are gone.
  for (const auto& stale : remove_stale_temporaries(directory_))
    spdlog::info("removed {}: left by an interrupted map save", stale.string());
}

CommandResult MapStore::check_name(const std::string& name) {
  if (!protocol::is_valid_map_name(name))
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "'" + name + "' is not a map name (1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot)");
  if (temporary_file_owner(name)) {
    // Such a file is not listed, and the next start may remove it as a save's leftover.
    return CommandResult::failure(ErrorCode::kBadParams,
                                  "'" + name + "' is named like a temporary file (NAME.tmp.NUMBER)");
  }
  return CommandResult::success();
}

CommandResult MapStore::save(const MlsMap& map, const LocalizationMap* localization, const std::string& name,
                             std::string* version) const {
  if (CommandResult checked = check_name(name); !checked.ok)
    return checked;
  try {
    const std::string bytes = serialize_map_file(map, localization);
    const std::string sha256 = sha256_hex(bytes);
    // The version first: a failure leaves the saved map as it was. The same bytes are the same version
    // (a map localized in and saved again).
    std::string saved_version;
    if (auto same = versions_.find_by_hash(name, sha256)) {
      saved_version = same->version;
    } else {
      saved_version = versions_.next_number(name);
      versions_.add({name, saved_version, bytes.size(), sha256, keyframe_heights(localization)}, bytes);
    }
    write_file_atomically(directory_ / name, bytes, Durability::kOnDisk);  // temporary, fsync, rename
    if (version != nullptr)
      *version = saved_version;
  } catch (const std::exception& error) {
    spdlog::warn("map save failed: {}", error.what());  // the whole story, paths too, for the log
    return CommandResult::failure(ErrorCode::kIoError, for_clients(error.what()));
  }
  spdlog::info("map saved to {}", (directory_ / name).string());
  return CommandResult::success();
}

MapStore::Loaded MapStore::load(const std::string& name) const {
  if (!protocol::is_valid_map_name(name))
    return {check_name(name), MlsMap(), std::nullopt, {}};
  return load_file(directory_ / name, name, "map named '" + name + "'");
}

MapStore::Loaded MapStore::load_version(const std::string& name, const std::string& version) const {
  if (!versions_.find(name, version)) {
    return {CommandResult::failure(ErrorCode::kNotFound, "no version '" + version.substr(0, 64) +
                                                             "' of map '" + name.substr(0, 64) + "'"),
            MlsMap(),
            std::nullopt,
            {}};
  }
  return load_file(versions_.file_of(name, version), name, "version " + version + " of map '" + name + "'");
}

MapStore::Loaded MapStore::load_file(const std::filesystem::path& path, const std::string& name,
                                     const std::string& label) const {
  std::error_code error;
  // A regular file inside the directory, never what a link points to (/etc/passwd, a map elsewhere).
  if (std::filesystem::symlink_status(path, error).type() != std::filesystem::file_type::regular)
    return {CommandResult::failure(ErrorCode::kNotFound, "no " + label), MlsMap(), std::nullopt, {}};
  const auto bytes = read_file_bytes(path);
  if (!bytes)
    return {CommandResult::failure(ErrorCode::kIoError, label + " could not be read"),
            MlsMap(),
            std::nullopt,
            {}};
  try {
    MapFile file = deserialize_map_file(*bytes, path.string());  // the whole file is checked
    const auto version = versions_.find_by_hash(name, sha256_hex(*bytes));
    return {CommandResult::success(), std::move(file.map), std::move(file.localization),
            version ? version->version : std::string()};
  } catch (const std::exception& failure) {
    spdlog::warn("map load failed: {}", failure.what());
    return {CommandResult::failure(ErrorCode::kCorruptFile, for_clients(failure.what())),
            MlsMap(),
            std::nullopt,
            {}};
  }
}

CommandResult MapStore::add_version(const std::string& name, const std::string& version,
                                    std::string_view bytes, std::string_view sha256) const {
  if (CommandResult checked = check_name(name); !checked.ok)
    return checked;
  if (!MapVersions::is_valid_version(version)) {
    return CommandResult::failure(
        ErrorCode::kBadParams,
        "a map version is 1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot");
  }
  const std::string hash = sha256_hex(bytes);
  std::string expected(sha256);
  std::transform(expected.begin(), expected.end(), expected.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!expected.empty() && expected != hash) {
    return CommandResult::failure(ErrorCode::kBadParams, "the file's SHA-256 is " + hash + ", not the hash " +
                                                             expected.substr(0, 64) + " it was sent with");
  }
  if (versions_.find(name, version)) {
    return CommandResult::failure(ErrorCode::kBadParams, "version " + version + " of map " + name +
                                                             " is there already: delete it first");
  }
  std::vector<double> heights;
  try {
    // Checked as a load checks a file, and as localizing in it needs.
    const MapFile file = deserialize_map_file(bytes, "(downloaded, version " + version + " of " + name + ")");
    if (!file.localization || file.localization->empty()) {
      return CommandResult::failure(ErrorCode::kCorruptFile,
                                    "the map has no localization data: it could not be localized in");
    }
    heights = keyframe_heights(&*file.localization);
  } catch (const std::exception& failure) {
    return CommandResult::failure(ErrorCode::kCorruptFile, failure.what());
  }
  try {
    versions_.add({name, version, bytes.size(), hash, std::move(heights)}, bytes);
  } catch (const std::exception& error) {
    spdlog::warn("map version store failed: {}", error.what());
    return CommandResult::failure(ErrorCode::kIoError, for_clients(error.what()));
  }
  spdlog::info("map version {} of {} stored ({} bytes, SHA-256 {})", version, name, bytes.size(), hash);
  return CommandResult::success();
}

std::string MapStore::for_clients(std::string message) const {
  // Files by their names: where the server keeps them is not a client's business.
  const std::string prefix = (directory_ / "").string();
  for (std::size_t at = message.find(prefix); at != std::string::npos; at = message.find(prefix, at))
    message.erase(at, prefix.size());
  // A temporary file's name carries the process id (NAME.tmp.PID): NAME.tmp.
  constexpr std::string_view kTemporary = ".tmp.";
  for (std::size_t at = message.find(kTemporary); at != std::string::npos;
       at = message.find(kTemporary, at)) {
    at += kTemporary.size() - 1;
    std::size_t digits = at + 1;
    while (digits < message.size() && message[digits] >= '0' && message[digits] <= '9')
      ++digits;
    message.erase(at, digits - at);
  }
  return message;
}

std::vector<MapFileInfo> MapStore::list() const {
  std::vector<MapFileInfo> maps;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory_, error)) {
    const std::string name = entry.path().filename().string();
    // Regular files only: a link in the directory is not listed (its target's size and date are not ours).
    if (!protocol::is_valid_map_name(name) || temporary_file_owner(name) ||
        entry.symlink_status(error).type() != std::filesystem::file_type::regular)
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

bool MapStore::is_mcap(const std::string& format) {
  return format == "mcap" || format == "mcap-uncompressed";
}

std::vector<std::uint8_t> MapStore::download(const std::string& format, const MlsMap& map,
                                             const LocalizationMap* localization, const DrivableMap* drivable,
                                             std::uint64_t version,
                                             std::span<const Eigen::Isometry3d> trajectory) {
  std::string bytes;
  if (is_mcap(format)) {
    if (map.patch_count() == 0)
      return {};
    bytes = ros2::map_as_mcap(
        {.map = &map,
         .drivable = drivable != nullptr && !drivable->grid.cells.empty() ? &drivable->grid : nullptr,
         .trajectory = trajectory,
         .stamp_ns = ros2::system_time_ns()},
        format == "mcap" ? mcap::Compression::kZstd : mcap::Compression::kNone);
  } else if (format == "strata" || format == "ply") {
    if (map.patch_count() == 0)
      return {};
    // The native file is the file a save writes, localization data and all: a map downloaded to move it
    // to another robot is localized in there (issue 63).
    bytes = format == "strata" ? serialize_map_file(map, localization) : mls_ply(map);
  } else if (format == "pgm" || format == "yaml") {
    if (drivable == nullptr || drivable->grid.cells.empty())
      return {};
    // The YAML names the image as a download saves it next to it (map.pgm), and the version whose image
    // it is: the map changes with every scan, and a PGM fetched later must be asked for by it.
    bytes = format == "pgm"
                ? ros_map_pgm(drivable->grid)
                : "# strata map version " + std::to_string(version) +
                      "; its image: GET /api/v1/map?format=pgm&version=" + std::to_string(version) + "\n" +
                      ros_map_yaml(drivable->grid, "map.pgm");
  }
  return {bytes.begin(), bytes.end()};
}

}  // namespace strata::pipeline

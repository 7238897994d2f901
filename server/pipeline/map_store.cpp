#include "server/pipeline/map_store.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

#include "core/files/temporary_files.hpp"
#include "core/mls/map_export.hpp"
#include "core/mls/mls_file.hpp"
#include "drivers/ros2/map_messages.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::pipeline {

MapStore::MapStore(std::filesystem::path directory) : directory_(std::move(directory)) {
  std::filesystem::create_directories(directory_);
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

CommandResult MapStore::save(const MlsMap& map, const LocalizationMap* localization,
                             const std::string& name) const {
  if (CommandResult checked = check_name(name); !checked.ok)
    return checked;
  try {
    save_map_file(map, localization, directory_ / name);  // atomic: temporary file, fsync, rename
  } catch (const std::exception& error) {
    spdlog::warn("map save failed: {}", error.what());  // the whole story, paths too, for the log
    return CommandResult::failure(ErrorCode::kIoError, for_clients(error.what()));
  }
  spdlog::info("map saved to {}", (directory_ / name).string());
  return CommandResult::success();
}

MapStore::Loaded MapStore::load(const std::string& name) const {
  if (!protocol::is_valid_map_name(name))
    return {check_name(name), MlsMap(), std::nullopt};
  const std::filesystem::path path = directory_ / name;
  std::error_code error;
  // A regular file inside the directory, never what a link points to (/etc/passwd, a map elsewhere).
  if (std::filesystem::symlink_status(path, error).type() != std::filesystem::file_type::regular)
    return {CommandResult::failure(ErrorCode::kNotFound, "no map named '" + name + "'"), MlsMap(),
            std::nullopt};
  try {
    MapFile file = load_map_file(path);  // the whole file is checked
    return {CommandResult::success(), std::move(file.map), std::move(file.localization)};
  } catch (const std::exception& failure) {
    spdlog::warn("map load failed: {}", failure.what());
    return {CommandResult::failure(ErrorCode::kCorruptFile, for_clients(failure.what())), MlsMap(),
            std::nullopt};
  }
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

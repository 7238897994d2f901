#include "server/pipeline/map_versions.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "core/files/atomic_file.hpp"
#include "core/files/temporary_files.hpp"
#include "server/pipeline/file_bytes.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::pipeline {
namespace {

constexpr std::string_view kFileSuffix = ".map";
constexpr std::string_view kMetaSuffix = ".meta";
constexpr std::size_t kMaxMetaBytes = 64 * 1024;

bool is_regular(const std::filesystem::path& path) {
  std::error_code error;
  return std::filesystem::symlink_status(path, error).type() == std::filesystem::file_type::regular;
}

std::optional<std::uint64_t> whole_number(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    return std::nullopt;
  return value;
}

}  // namespace

MapVersions::MapVersions(const std::filesystem::path& maps_dir) : root_(maps_dir / ".versions") {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(root_, error)) {
    if (entry.is_directory(error) && !entry.is_symlink(error)) {
      for (const auto& stale : remove_stale_temporaries(entry.path()))
        spdlog::info("removed {}: left by an interrupted map version write", stale.string());
    }
  }
}

bool MapVersions::is_valid_version(std::string_view version) {
  return protocol::is_valid_map_name(version);  // the same characters: both are file names
}

std::filesystem::path MapVersions::file_of(const std::string& name, const std::string& version) const {
  return root_ / name / (version + std::string(kFileSuffix));
}

std::filesystem::path MapVersions::meta_of(const std::string& name, const std::string& version) const {
  return root_ / name / (version + std::string(kMetaSuffix));
}

std::vector<MapVersionInfo> MapVersions::versions_of(const std::filesystem::path& name_dir) const {
  std::vector<MapVersionInfo> versions;
  const std::string name = name_dir.filename().string();
  if (!protocol::is_valid_map_name(name))
    return versions;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(name_dir, error)) {
    const std::string file = entry.path().filename().string();
    if (!file.ends_with(kFileSuffix) || !is_regular(entry.path()))
      continue;
    const std::string version = file.substr(0, file.size() - kFileSuffix.size());
    if (!is_valid_version(version) || temporary_file_owner(file))
      continue;
    MapVersionInfo info{name, version, entry.file_size(error), {}, {}};
    const auto meta_text = read_file_bytes(meta_of(name, version));
    if (!meta_text || meta_text->size() > kMaxMetaBytes) {
      spdlog::warn("map version {} {}: no meta file, not listed", name, version);
      continue;
    }
    const nlohmann::json meta = nlohmann::json::parse(*meta_text, nullptr, false);
    if (!meta.is_object() || !meta.value("sha256", nlohmann::json()).is_string()) {
      spdlog::warn("map version {} {}: its meta file is not readable, not listed", name, version);
      continue;
    }
    info.sha256 = meta["sha256"].get<std::string>();
    if (const auto heights = meta.find("heights"); heights != meta.end() && heights->is_array()) {
      for (const auto& height : *heights) {
        if (height.is_number())
          info.heights.push_back(height.get<double>());
      }
    }
    versions.push_back(std::move(info));
  }
  // Whole numbers in their order, before other names in theirs.
  std::sort(versions.begin(), versions.end(), [](const MapVersionInfo& a, const MapVersionInfo& b) {
    const auto na = whole_number(a.version);
    const auto nb = whole_number(b.version);
    if (na && nb)
      return *na < *nb;
    if (na.has_value() != nb.has_value())
      return na.has_value();
    return a.version < b.version;
  });
  return versions;
}

std::vector<MapVersionInfo> MapVersions::list() const {
  std::vector<std::filesystem::path> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(root_, error)) {
    if (entry.is_directory(error) && !entry.is_symlink(error))
      names.push_back(entry.path());
  }
  std::sort(names.begin(), names.end());
  std::vector<MapVersionInfo> all;
  for (const auto& name_dir : names) {
    auto versions = versions_of(name_dir);
    std::move(versions.begin(), versions.end(), std::back_inserter(all));
  }
  return all;
}

std::optional<MapVersionInfo> MapVersions::find(const std::string& name, const std::string& version) const {
  if (!protocol::is_valid_map_name(name) || !is_valid_version(version))
    return std::nullopt;
  for (auto& info : versions_of(root_ / name)) {
    if (info.version == version)
      return std::move(info);
  }
  return std::nullopt;
}

std::optional<MapVersionInfo> MapVersions::find_by_hash(const std::string& name,
                                                        const std::string& sha256) const {
  if (!protocol::is_valid_map_name(name))
    return std::nullopt;
  const auto versions = versions_of(root_ / name);
  const auto found = std::find_if(versions.rbegin(), versions.rend(),
                                  [&sha256](const MapVersionInfo& info) { return info.sha256 == sha256; });
  if (found == versions.rend())
    return std::nullopt;
  return *found;
}

std::string MapVersions::next_number(const std::string& name) const {
  std::uint64_t largest = 0;
  for (const auto& info : versions_of(root_ / name))
    largest = std::max(largest, whole_number(info.version).value_or(0));
  return std::to_string(largest + 1);
}

void MapVersions::add(const MapVersionInfo& info, std::string_view bytes) const {
  if (!protocol::is_valid_map_name(info.name) || !is_valid_version(info.version))
    throw std::runtime_error("not a map name and version: " + info.name + " " + info.version);
  const std::filesystem::path file = file_of(info.name, info.version);
  const std::lock_guard lock(writing_);
  if (std::filesystem::exists(file))
    throw std::runtime_error("version " + info.version + " of " + info.name + " is there already");
  std::filesystem::create_directories(file.parent_path());
  const nlohmann::json meta{{"sha256", info.sha256}, {"bytes", bytes.size()}, {"heights", info.heights}};
  // The meta first: a version is listed once its file is there, and then its meta is too.
  write_file_atomically(meta_of(info.name, info.version), meta.dump(), Durability::kOnDisk);
  write_file_atomically(file, bytes, Durability::kOnDisk);
}

MapVersionFile MapVersions::read(const std::string& name, const std::string& version) const {
  MapVersionFile result;
  auto info = find(name, version);
  if (!info) {
    result.result = CommandResult::failure(ErrorCode::kNotFound, "no version " + version + " of map " + name);
    return result;
  }
  auto bytes = read_file_bytes(file_of(name, version));
  if (!bytes || bytes->size() != info->bytes) {
    result.result = CommandResult::failure(ErrorCode::kIoError,
                                           "version " + version + " of map " + name + " could not be read");
    return result;
  }
  result.info = std::move(*info);
  result.bytes = std::move(*bytes);
  return result;
}

bool MapVersions::remove(const std::string& name, const std::string& version) const {
  if (!find(name, version))
    return false;
  const std::lock_guard lock(writing_);
  std::error_code error;
  // The file first: without it the version is gone, whatever happens to the meta.
  if (!std::filesystem::remove(file_of(name, version), error))
    return false;
  std::filesystem::remove(meta_of(name, version), error);
  std::filesystem::remove(root_ / name, error);  // only when empty
  return true;
}

}  // namespace strata::pipeline

#include "core/mls/mls_file.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>

#include "core/files/atomic_file.hpp"

namespace strata {
namespace {

static_assert(std::endian::native == std::endian::little, "the native map format is written little-endian");

constexpr char kMagic[8] = {'S', 'T', 'R', 'A', 'T', 'M', 'L', 'S'};
/// 2: a flags byte per patch (MlsPatch::kDriven). 3: the localization map after the tiles. 4: the flag
/// MlsPatch::kTrack (an older build would call it corrupt). Version 1 files (no flags) are still read.
constexpr std::uint32_t kFormatVersion = 4;
constexpr std::uint32_t kOldestFormatVersion = 1;
constexpr std::size_t kHeaderBytes = sizeof(kMagic) + sizeof(std::uint32_t) + sizeof(std::uint64_t);
constexpr std::size_t kChecksumBytes = sizeof(std::uint64_t);

std::uint64_t fnv1a64(const char* data, std::size_t size) {
  std::uint64_t hash = 0xCBF29CE484222325ULL;
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 0x100000001B3ULL;
  }
  return hash;
}

template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

/// Reads fields from the verified buffer; running out is still checked, so a lying count cannot read past.
class Reader {
 public:
  Reader(std::string_view data, std::size_t end, const std::string& name)
      : data_(data), end_(end), name_(name) {}
  template <typename T>
  T get() {
    if (end_ - position_ < sizeof(T))
      fail("truncated: ends inside a record");
    T value;
    std::memcpy(&value, data_.data() + position_, sizeof(T));
    position_ += sizeof(T);
    return value;
  }
  [[nodiscard]] std::size_t position() const { return position_; }
  void seek(std::size_t position) { position_ = position; }
  [[noreturn]] void fail(const std::string& what) const {
    throw MlsFileError("MLS map file " + name_ + ": " + what);
  }

 private:
  std::string_view data_;
  std::size_t end_;
  std::size_t position_ = 0;
  const std::string& name_;
};

void encode_localization(std::string& out, const LocalizationMap* localization) {
  put<std::uint8_t>(out, localization != nullptr ? 1 : 0);
  if (localization == nullptr)
    return;
  put(out, localization->voxel);
  put<std::uint64_t>(out, localization->keyframe_poses.size());
  for (const Eigen::Isometry3d& pose : localization->keyframe_poses) {
    const Eigen::Quaterniond q(pose.linear());
    for (const double value :
         {pose.translation().x(), pose.translation().y(), pose.translation().z(), q.w(), q.x(), q.y(), q.z()})
      put(out, value);
  }
  put<std::uint64_t>(out, localization->points.size());
  for (const Eigen::Vector3f& p : localization->points)
    for (const float value : {p.x(), p.y(), p.z()})
      put(out, value);
}

LocalizationMap decode_localization(Reader& fields, std::size_t body) {
  LocalizationMap localization;
  localization.voxel = fields.get<double>();
  if (!(localization.voxel > 0.0) || !std::isfinite(localization.voxel))
    fields.fail("invalid localization map voxel");
  // Counts are checked against the bytes left before anything is reserved: a lying count cannot allocate.
  const auto poses = fields.get<std::uint64_t>();
  constexpr std::size_t kPoseBytes = 7 * sizeof(double);
  if (poses > (body - fields.position()) / kPoseBytes)
    fields.fail("truncated: the localization map's keyframe poses run past its end");
  localization.keyframe_poses.reserve(poses);
  for (std::uint64_t i = 0; i < poses; ++i) {
    // One field per statement: a function's arguments are evaluated in no fixed order.
    std::array<double, 7> v{};
    for (double& value : v)
      value = fields.get<double>();
    const Eigen::Vector3d t(v[0], v[1], v[2]);
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (!t.allFinite() || !q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-6)
      fields.fail("invalid keyframe pose in the localization map");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.normalized().toRotationMatrix();
    pose.translation() = t;
    localization.keyframe_poses.push_back(pose);
  }
  const auto points = fields.get<std::uint64_t>();
  constexpr std::size_t kPointBytes = 3 * sizeof(float);
  if (points > (body - fields.position()) / kPointBytes)
    fields.fail("truncated: the localization map's points run past its end");
  localization.points.reserve(points);
  for (std::uint64_t i = 0; i < points; ++i) {
    Eigen::Vector3f p;
    for (int axis = 0; axis < 3; ++axis)
      p[axis] = fields.get<float>();
    if (!p.allFinite())
      fields.fail("invalid point in the localization map");
    localization.points.push_back(p);
  }
  return localization;
}

std::string encode(const MlsMap& map, const LocalizationMap* localization) {
  std::string out;
  out.append(kMagic, sizeof(kMagic));
  put(out, kFormatVersion);
  put<std::uint64_t>(out, 0);  // total size, filled in below
  const MlsConfig& c = map.config();
  put(out, c.resolution);
  put(out, c.gap);
  put(out, c.vertical_threshold);
  put(out, c.sigma_base);
  put(out, c.sigma_per_metre);
  put(out, c.min_range);
  put<std::int32_t>(out, c.max_evidence);
  put<std::int32_t>(out, c.free_space_ray_stride);
  put(out, c.free_space_stop_short);
  put(out, c.free_space_height_margin);
  put<std::uint32_t>(out, kMlsTileBits);  // tile indices mean nothing without the tile size
  put<std::uint64_t>(out, map.version());

  std::vector<TileIndex> tiles = map.tile_indices();
  std::sort(tiles.begin(), tiles.end(),
            [](const TileIndex& a, const TileIndex& b) { return std::tie(a.y, a.x) < std::tie(b.y, b.x); });
  put<std::uint64_t>(out, tiles.size());
  std::string counts(kMlsTileCells, '\0');
  std::string patches;
  for (const TileIndex& index : tiles) {
    const MlsTile& tile = *map.find_tile(index);
    patches.clear();
    std::uint32_t total = 0;
    for (int local = 0; local < kMlsTileCells; ++local) {
      unsigned count = 0;
      tile.for_each_patch(local, [&](const MlsPatch& p) {
        put(patches, p.mean);
        put(patches, p.variance);
        put(patches, p.depth);
        put(patches, p.evidence);
        put(patches, p.flags);
        ++count;
      });
      if (count > 255)
        throw MlsFileError("MLS map: a cell holds more than 255 patches; the format cannot store it");
      counts[static_cast<std::size_t>(local)] = static_cast<char>(count);
      total += count;
    }
    put<std::int32_t>(out, index.x);
    put<std::int32_t>(out, index.y);
    put<std::uint64_t>(out, tile.version);
    put<std::uint32_t>(out, total);
    out += counts;
    out += patches;
  }
  encode_localization(out, localization);
  const std::uint64_t size = out.size() + kChecksumBytes;
  std::memcpy(out.data() + sizeof(kMagic) + sizeof(std::uint32_t), &size, sizeof(size));
  put(out, fnv1a64(out.data(), out.size()));
  return out;
}

/// Refuses a map whose tiles from `low` to `high` span more cells than kMaxMapFileCells, as the tiles are
/// read: a lying tile index cannot make the load allocate.
void check_extent(Reader& fields, const TileIndex& low, const TileIndex& high, double resolution) {
  const auto span = [](int from, int to) {
    return (static_cast<std::uint64_t>(static_cast<std::int64_t>(to) - from) + 1) * kMlsTileSize;
  };
  const std::uint64_t width = span(low.x, high.x);
  const std::uint64_t height = span(low.y, high.y);
  // Each side alone first: their product could overflow.
  if (width <= kMaxMapFileCells && height <= kMaxMapFileCells && width * height <= kMaxMapFileCells)
    return;
  char text[200];
  std::snprintf(text, sizeof text,
                "the map spans %.0f by %.0f m: more than the %llu million cells (%.2f km^2 at %.2f m) a map "
                "may cover",
                static_cast<double>(width) * resolution, static_cast<double>(height) * resolution,
                static_cast<unsigned long long>(kMaxMapFileCells / 1'000'000),
                static_cast<double>(kMaxMapFileCells) * resolution * resolution / 1e6, resolution);
  fields.fail(text);
}

MapFile decode(std::string_view data, const std::string& name) {
  Reader reader(data, data.size(), name);
  if (data.size() < kHeaderBytes || std::memcmp(data.data(), kMagic, sizeof(kMagic)) != 0)
    reader.fail("not a Strata MLS map (bad magic)");
  reader.seek(sizeof(kMagic));
  const auto format = reader.get<std::uint32_t>();
  if (format < kOldestFormatVersion || format > kFormatVersion)
    reader.fail("unsupported format version " + std::to_string(format) + " (this build reads " +
                std::to_string(kOldestFormatVersion) + " to " + std::to_string(kFormatVersion) + ")");
  const auto declared = reader.get<std::uint64_t>();
  if (data.size() < declared)
    reader.fail("truncated: " + std::to_string(data.size()) + " bytes of " + std::to_string(declared));
  if (data.size() != declared || declared < kHeaderBytes + kChecksumBytes)
    reader.fail("corrupted: size " + std::to_string(data.size()) + " does not match the header's " +
                std::to_string(declared));
  const std::size_t body = data.size() - kChecksumBytes;
  std::uint64_t stored = 0;
  std::memcpy(&stored, data.data() + body, sizeof(stored));
  if (stored != fnv1a64(data.data(), body))
    reader.fail("corrupted: checksum mismatch");

  Reader fields(data, body, name);
  fields.seek(kHeaderBytes);
  MlsConfig config;
  config.resolution = fields.get<double>();
  config.gap = fields.get<double>();
  config.vertical_threshold = fields.get<double>();
  config.sigma_base = fields.get<double>();
  config.sigma_per_metre = fields.get<double>();
  config.min_range = fields.get<double>();
  config.max_evidence = fields.get<std::int32_t>();
  config.free_space_ray_stride = fields.get<std::int32_t>();
  config.free_space_stop_short = fields.get<double>();
  config.free_space_height_margin = fields.get<double>();
  if (!(config.resolution > 0.0) || !std::isfinite(config.resolution) || !(config.gap > 0.0) ||
      config.max_evidence < 1 || config.max_evidence > 255)
    fields.fail("invalid map configuration");
  const auto tile_bits = fields.get<std::uint32_t>();
  if (tile_bits != kMlsTileBits)
    fields.fail("written with tiles of " + std::to_string(1U << (tile_bits & 31U)) +
                " cells a side, this build uses " + std::to_string(kMlsTileSize));
  MapFile file{.map = MlsMap(config), .localization = std::nullopt, .format_version = format};
  MlsMap& map = file.map;
  map.set_version(fields.get<std::uint64_t>());
  const auto tile_count = fields.get<std::uint64_t>();
  TileIndex low{std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  TileIndex high{std::numeric_limits<int>::min(), std::numeric_limits<int>::min()};
  for (std::uint64_t t = 0; t < tile_count; ++t) {
    const TileIndex index{fields.get<std::int32_t>(), fields.get<std::int32_t>()};
    // Every cell of the tile needs an int index: index * kMlsTileSize + (kMlsTileSize - 1) must not overflow.
    constexpr int kMinTile = std::numeric_limits<int>::min() / kMlsTileSize;
    constexpr int kMaxTile = std::numeric_limits<int>::max() / kMlsTileSize;
    if (index.x < kMinTile || index.x > kMaxTile || index.y < kMinTile || index.y > kMaxTile)
      fields.fail("tile index (" + std::to_string(index.x) + ", " + std::to_string(index.y) +
                  ") out of range");
    low = {std::min(low.x, index.x), std::min(low.y, index.y)};
    high = {std::max(high.x, index.x), std::max(high.y, index.y)};
    check_extent(fields, low, high, config.resolution);
    if (map.find_tile(index) != nullptr)
      fields.fail("tile (" + std::to_string(index.x) + ", " + std::to_string(index.y) + ") appears twice");
    map.set_tile_version(index, fields.get<std::uint64_t>());
    const auto total = fields.get<std::uint32_t>();
    std::array<std::uint8_t, kMlsTileCells> counts{};
    std::uint32_t sum = 0;
    for (std::uint8_t& count : counts) {
      count = fields.get<std::uint8_t>();
      sum += count;
    }
    if (sum != total || total > MlsTile::kMaxPatches)
      fields.fail("tile patch counts disagree");
    for (int local = 0; local < kMlsTileCells; ++local) {
      const CellIndex cell{index.x * kMlsTileSize + local % kMlsTileSize,
                           index.y * kMlsTileSize + local / kMlsTileSize};
      float previous_top = -std::numeric_limits<float>::infinity();
      const std::uint8_t known_flags = format >= 4 ? MlsPatch::kKnownFlags : MlsPatch::kDriven;
      for (unsigned i = 0; i < counts[static_cast<std::size_t>(local)]; ++i) {
        MlsPatch patch;
        patch.mean = fields.get<float>();
        patch.variance = fields.get<float>();
        patch.depth = fields.get<float>();
        patch.evidence = fields.get<std::uint8_t>();
        patch.flags = format >= 2 ? fields.get<std::uint8_t>() : std::uint8_t{0};
        if (!std::isfinite(patch.mean) || !std::isfinite(patch.variance) || !std::isfinite(patch.depth) ||
            patch.depth < 0.0F || patch.variance < 0.0F || patch.evidence == 0 ||
            patch.mean <= previous_top || (patch.flags & ~known_flags) != 0)
          fields.fail("invalid patch in tile (" + std::to_string(index.x) + ", " + std::to_string(index.y) +
                      ")");
        previous_top = patch.mean;
        if (!map.append_patch(cell, patch))
          fields.fail("too many patches in a tile");
      }
    }
  }
  if (format >= 3 && fields.get<std::uint8_t>() != 0)
    file.localization = decode_localization(fields, body);
  if (fields.position() != body)
    fields.fail("corrupted: trailing bytes after the last record");
  return file;
}

std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw MlsFileError("MLS map file " + path.string() + ": cannot open");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw MlsFileError("MLS map file " + path.string() + ": read error");
  return data;
}

}  // namespace

std::uint32_t map_file_format_version() {
  return kFormatVersion;
}

std::string serialize_mls_map(const MlsMap& map) {
  return encode(map, nullptr);
}

std::string serialize_map_file(const MlsMap& map, const LocalizationMap* localization) {
  return encode(map, localization);
}

MlsMap deserialize_mls_map(std::string_view data, const std::string& source) {
  return decode(data, source).map;
}

MapFile deserialize_map_file(std::string_view data, const std::string& source) {
  return decode(data, source);
}

void save_mls_map(const MlsMap& map, const std::filesystem::path& path) {
  save_map_file(map, nullptr, path);
}

void save_map_file(const MlsMap& map, const LocalizationMap* localization,
                   const std::filesystem::path& path) {
  try {
    write_file_atomically(path, encode(map, localization), Durability::kOnDisk);
  } catch (const FileWriteError& error) {
    throw MlsFileError(error.what());
  }
}

MlsMap load_mls_map(const std::filesystem::path& path) {
  return decode(read_whole_file(path), path.string()).map;
}

MapFile load_map_file(const std::filesystem::path& path) {
  return decode(read_whole_file(path), path.string());
}

void load_mls_map_into(const std::filesystem::path& path, MlsMap& map) {
  map = load_mls_map(path);
}

}  // namespace strata

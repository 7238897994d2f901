#include "drivers/io/pcd_reader.hpp"

#include <lzf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "drivers/io/binary_field.hpp"
#include "drivers/io/point_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

struct PcdField {
  std::string name;
  ScalarType type;
  std::size_t count = 1;
  std::size_t offset = 0;  ///< bytes from the start of a point record (binary)
  std::size_t column = 0;  ///< first value of this field in an ascii line
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t points = 0;
  bool points_given = false;
  std::string data;
  std::size_t record_size = 0;
  std::size_t values_per_point = 0;
};

/// 2^40: more points, bytes or fields than any PCD file holds, and products of two stay far from overflow.
constexpr double kMaxCount = 1099511627776.0;

std::size_t to_count(const std::filesystem::path& path, std::string_view keyword, std::string_view field) {
  const std::optional<double> value = parse_number(field);
  // Compared before the cast: converting a double beyond size_t's range is undefined (the PLY reader's
  // element count had that bug; fuzzing found it).
  if (!value || !(*value >= 0.0 && *value <= kMaxCount) || *value != std::floor(*value))
    throw PointFileError(path, "header " + std::string(keyword) + ": '" + std::string(field) +
                                   "' is not a non-negative integer");
  return static_cast<std::size_t>(*value);
}

PcdHeader read_header(std::istream& in, const std::filesystem::path& path) {
  PcdHeader header;
  std::vector<std::size_t> sizes;
  std::vector<char> types;
  std::vector<std::size_t> counts;
  std::size_t width = 0;
  std::size_t height = 1;
  bool width_given = false;
  std::string line;
  while (std::getline(in, line)) {
    const std::vector<std::string_view> words = split_fields(line);
    if (words.empty() || words[0].starts_with('#'))
      continue;
    const std::string_view key = words[0];
    if (key == "VERSION" || key == "VIEWPOINT") {
      continue;
    } else if (key == "FIELDS") {
      for (std::size_t i = 1; i < words.size(); ++i)
        header.fields.push_back({.name = std::string(words[i])});
    } else if (key == "SIZE") {
      for (std::size_t i = 1; i < words.size(); ++i)
        sizes.push_back(to_count(path, key, words[i]));
    } else if (key == "TYPE") {
      for (std::size_t i = 1; i < words.size(); ++i)
        types.push_back(words[i].size() == 1 ? words[i][0] : '?');
    } else if (key == "COUNT") {
      for (std::size_t i = 1; i < words.size(); ++i)
        counts.push_back(to_count(path, key, words[i]));
    } else if (key == "WIDTH" && words.size() == 2) {
      width = to_count(path, key, words[1]);
      width_given = true;
    } else if (key == "HEIGHT" && words.size() == 2) {
      height = to_count(path, key, words[1]);
    } else if (key == "POINTS" && words.size() == 2) {
      header.points = to_count(path, key, words[1]);
      header.points_given = true;
    } else if (key == "DATA" && words.size() == 2) {
      header.data = std::string(words[1]);
      break;
    } else {
      throw PointFileError(path, "not a PCD file: unexpected header line '" + line + "'");
    }
  }
  if (header.data.empty())
    throw PointFileError(path, "PCD header has no DATA line (not a PCD file, or truncated header)");
  if (header.fields.empty())
    throw PointFileError(path, "PCD header has no FIELDS");
  if (counts.empty())
    counts.assign(header.fields.size(), 1);
  if (sizes.size() != header.fields.size() || types.size() != header.fields.size() ||
      counts.size() != header.fields.size())
    throw PointFileError(path, "PCD header: FIELDS, SIZE, TYPE and COUNT list different numbers of fields");
  if (!header.points_given) {
    if (!width_given)
      throw PointFileError(path, "PCD header gives neither POINTS nor WIDTH");
    if (height != 0 && width > static_cast<std::size_t>(kMaxCount) / height)
      throw PointFileError(path, "PCD header: WIDTH x HEIGHT is too many points");
    header.points = width * height;
  }
  if (header.points > static_cast<std::size_t>(kMaxCount))
    throw PointFileError(path, "PCD header: " + std::to_string(header.points) + " points is too many");
  for (std::size_t i = 0; i < header.fields.size(); ++i) {
    PcdField& field = header.fields[i];
    const std::size_t size = sizes[i];
    const char type = types[i];
    const bool size_ok =
        type == 'F' ? (size == 4 || size == 8) : (size == 1 || size == 2 || size == 4 || size == 8);
    if ((type != 'F' && type != 'I' && type != 'U') || !size_ok)
      throw PointFileError(path, "PCD field '" + field.name + "' has unknown type " + std::string(1, type) +
                                     " of size " + std::to_string(size));
    field.type = {type == 'F'   ? ScalarKind::kFloat
                  : type == 'I' ? ScalarKind::kInt
                                : ScalarKind::kUnsigned,
                  size};
    field.count = counts[i];
    field.offset = header.record_size;
    field.column = header.values_per_point;
    header.record_size += size * field.count;
    header.values_per_point += field.count;
    if (header.record_size > static_cast<std::size_t>(kMaxCount))
      throw PointFileError(path, "PCD header: a point record of over 2^40 bytes");
  }
  return header;
}

std::array<const PcdField*, 3> xyz_fields(const PcdHeader& header, const std::filesystem::path& path) {
  std::array<const PcdField*, 3> xyz{};
  const std::array<std::string_view, 3> names{"x", "y", "z"};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    for (const PcdField& field : header.fields) {
      if (field.name == names[axis])
        xyz[axis] = &field;
    }
    if (xyz[axis] == nullptr)
      throw PointFileError(path, "PCD file has no '" + std::string(names[axis]) + "' field");
  }
  return xyz;
}

/// The "time" field (when each point was measured), if the file has one with a single value per point.
const PcdField* time_field(const PcdHeader& header) {
  for (const PcdField& field : header.fields) {
    if (field.name == "time" && field.count == 1)
      return &field;
  }
  return nullptr;
}

void read_ascii(std::istream& in, const PcdHeader& header, const std::filesystem::path& path,
                LoadedCloud& cloud) {
  const std::array<const PcdField*, 3> xyz = xyz_fields(header, path);
  const PcdField* time = time_field(header);
  std::string line;
  std::size_t read = 0;
  while (read < header.points && std::getline(in, line)) {
    const std::vector<std::string_view> values = split_fields(line);
    if (values.empty())
      continue;
    if (values.size() < header.values_per_point)
      throw PointFileError(path, "point " + std::to_string(read) + " has " + std::to_string(values.size()) +
                                     " values, the header declares " +
                                     std::to_string(header.values_per_point));
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      const std::optional<double> value = parse_number(values[xyz[static_cast<std::size_t>(axis)]->column]);
      if (!value)
        throw PointFileError(path, "point " + std::to_string(read) + ": '" +
                                       std::string(values[xyz[static_cast<std::size_t>(axis)]->column]) +
                                       "' is not a number");
      p[axis] = *value;
    }
    std::optional<double> when;
    if (time != nullptr) {
      when = parse_number(values[time->column]);
      if (!when)
        throw PointFileError(path, "point " + std::to_string(read) + ": time '" +
                                       std::string(values[time->column]) + "' is not a number");
    }
    add_finite(cloud, p, when);
    ++read;
  }
  if (read < header.points)
    throw PointFileError(
        path, "truncated: " + std::to_string(read) + " of " + std::to_string(header.points) + " points");
}

std::vector<unsigned char> read_rest(std::istream& in) {
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void read_binary(std::istream& in, const PcdHeader& header, const std::filesystem::path& path,
                 LoadedCloud& cloud) {
  const std::array<const PcdField*, 3> xyz = xyz_fields(header, path);
  const PcdField* time = time_field(header);
  const std::vector<unsigned char> data = read_rest(in);
  if (header.record_size != 0 && header.points > data.size() / header.record_size)
    throw PointFileError(path, "truncated: " + std::to_string(data.size()) + " data bytes, " +
                                   std::to_string(header.points) + " points of " +
                                   std::to_string(header.record_size) + " bytes");
  const std::size_t needed = header.points * header.record_size;
  if (data.size() < needed)
    throw PointFileError(path, "truncated: " + std::to_string(data.size()) + " data bytes, " +
                                   std::to_string(header.points) + " points need " + std::to_string(needed));
  for (std::size_t i = 0; i < header.points; ++i) {
    const unsigned char* record = data.data() + i * header.record_size;
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      const PcdField& field = *xyz[static_cast<std::size_t>(axis)];
      p[axis] = read_scalar(record + field.offset, field.type, false);
    }
    add_finite(cloud, p,
               time != nullptr ? std::optional(read_scalar(record + time->offset, time->type, false))
                               : std::nullopt);
  }
}

void read_binary_compressed(std::istream& in, const PcdHeader& header, const std::filesystem::path& path,
                            LoadedCloud& cloud) {
  const std::array<const PcdField*, 3> xyz = xyz_fields(header, path);
  const PcdField* time = time_field(header);
  const std::vector<unsigned char> data = read_rest(in);
  if (data.size() < 8)
    throw PointFileError(path, "truncated: binary_compressed data has no size words");
  std::uint32_t compressed_size = 0;
  std::uint32_t uncompressed_size = 0;
  std::memcpy(&compressed_size, data.data(), 4);  // PCL writes these little-endian, as the machine does
  std::memcpy(&uncompressed_size, data.data() + 4, 4);
  if (data.size() - 8 < compressed_size)
    throw PointFileError(path, "truncated: " + std::to_string(data.size() - 8) + " compressed bytes of " +
                                   std::to_string(compressed_size));
  if (header.record_size != 0 &&
      header.points > std::numeric_limits<std::uint32_t>::max() / header.record_size)
    throw PointFileError(path, "binary_compressed data unpacks to " + std::to_string(uncompressed_size) +
                                   " bytes, " + std::to_string(header.points) + " points of " +
                                   std::to_string(header.record_size) + " bytes need more");
  const std::size_t needed = header.points * header.record_size;
  if (uncompressed_size != needed)
    throw PointFileError(path, "binary_compressed data unpacks to " + std::to_string(uncompressed_size) +
                                   " bytes, " + std::to_string(header.points) + " points need " +
                                   std::to_string(needed));
  std::vector<unsigned char> unpacked(needed);
  if (needed > 0 && lzf_decompress(data.data() + 8, compressed_size, unpacked.data(),
                                   static_cast<unsigned>(needed)) != needed)
    throw PointFileError(path, "binary_compressed data is corrupt (LZF decompression failed)");
  // Unpacked, each field is stored for all points before the next field: x x x ... y y y ... z z z ...
  for (std::size_t i = 0; i < header.points; ++i) {
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      const PcdField& field = *xyz[static_cast<std::size_t>(axis)];
      const std::size_t field_bytes = field.type.size * field.count;
      p[axis] =
          read_scalar(unpacked.data() + field.offset * header.points + i * field_bytes, field.type, false);
    }
    add_finite(cloud, p,
               time != nullptr ? std::optional(read_scalar(
                                     unpacked.data() + time->offset * header.points + i * time->type.size,
                                     time->type, false))
                               : std::nullopt);
  }
}

}  // namespace

LoadedCloud read_pcd(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_pcd(in, path);
}

LoadedCloud read_pcd(std::istream& in, const std::filesystem::path& path) {
  const PcdHeader header = read_header(in, path);
  LoadedCloud cloud;
  cloud.points.reserve(std::min<std::size_t>(header.points, std::size_t{1} << 24));  // a header may lie
  if (header.data == "ascii")
    read_ascii(in, header, path, cloud);
  else if (header.data == "binary")
    read_binary(in, header, path, cloud);
  else if (header.data == "binary_compressed")
    read_binary_compressed(in, header, path, cloud);
  else
    throw PointFileError(path, "unknown PCD DATA type '" + header.data + "'");
  return cloud;
}

}  // namespace strata::io

#include "drivers/io/ply_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "drivers/io/binary_field.hpp"
#include "drivers/io/point_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

/// 2^40: more elements or list items than any PLY file holds (checked before converting a count to size_t).
constexpr double kMaxPlyCount = 1099511627776.0;

struct PlyProperty {
  std::string name;
  ScalarType type;
  bool is_list = false;
  ScalarType count_type;  ///< lists only
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

std::optional<ScalarType> scalar_type(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, ScalarType>, 16> kTypes{{
      {"char", {ScalarKind::kInt, 1}},
      {"int8", {ScalarKind::kInt, 1}},
      {"uchar", {ScalarKind::kUnsigned, 1}},
      {"uint8", {ScalarKind::kUnsigned, 1}},
      {"short", {ScalarKind::kInt, 2}},
      {"int16", {ScalarKind::kInt, 2}},
      {"ushort", {ScalarKind::kUnsigned, 2}},
      {"uint16", {ScalarKind::kUnsigned, 2}},
      {"int", {ScalarKind::kInt, 4}},
      {"int32", {ScalarKind::kInt, 4}},
      {"uint", {ScalarKind::kUnsigned, 4}},
      {"uint32", {ScalarKind::kUnsigned, 4}},
      {"float", {ScalarKind::kFloat, 4}},
      {"float32", {ScalarKind::kFloat, 4}},
      {"double", {ScalarKind::kFloat, 8}},
      {"float64", {ScalarKind::kFloat, 8}},
  }};
  for (const auto& [type_name, type] : kTypes) {
    if (type_name == name)
      return type;
  }
  return std::nullopt;
}

/// Reads values one by one from either encoding, so elements before the vertices (rare, but legal) and
/// list properties are skipped the same way.
class PlyValues {
 public:
  PlyValues(std::istream& in, PlyFormat format, const std::filesystem::path& path)
      : in_(in), format_(format), path_(path) {}

  double next(ScalarType type) {
    if (format_ == PlyFormat::kAscii) {
      while (position_ >= words_.size()) {
        if (!std::getline(in_, line_))
          throw PointFileError(path_, "truncated: the data ends before the declared vertex count");
        words_ = split_fields(line_);
        position_ = 0;
      }
      const std::optional<double> value = parse_number(words_[position_]);
      if (!value)
        throw PointFileError(path_, "'" + std::string(words_[position_]) + "' is not a number");
      ++position_;
      return *value;
    }
    unsigned char bytes[8];
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(type.size)))
      throw PointFileError(path_, "truncated: the data ends before the declared vertex count");
    return read_scalar(bytes, type, format_ == PlyFormat::kBinaryBigEndian);
  }

 private:
  std::istream& in_;
  PlyFormat format_;
  const std::filesystem::path& path_;
  std::string line_;
  std::vector<std::string_view> words_;
  std::size_t position_ = 0;
};

}  // namespace

LoadedCloud read_ply(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_ply(in, path);
}

LoadedCloud read_ply(std::istream& in, const std::filesystem::path& path) {
  std::string line;
  if (!std::getline(in, line) || (line != "ply" && line != "ply\r"))
    throw PointFileError(path, "not a PLY file: the first line is not 'ply'");
  std::optional<PlyFormat> format;
  std::vector<PlyElement> elements;
  bool header_ended = false;
  while (std::getline(in, line)) {
    const std::vector<std::string_view> words = split_fields(line);
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info")
      continue;
    if (words[0] == "end_header") {
      header_ended = true;
      break;
    }
    if (words[0] == "format" && words.size() >= 2) {
      if (words[1] == "ascii")
        format = PlyFormat::kAscii;
      else if (words[1] == "binary_little_endian")
        format = PlyFormat::kBinaryLittleEndian;
      else if (words[1] == "binary_big_endian")
        format = PlyFormat::kBinaryBigEndian;
      else
        throw PointFileError(path, "unknown PLY format '" + std::string(words[1]) + "'");
    } else if (words[0] == "element" && words.size() == 3) {
      const std::optional<double> count = parse_number(words[2]);
      // Checked before the cast: a double beyond size_t's range is undefined to convert (found by fuzzing).
      if (!count || !(*count >= 0.0 && *count <= kMaxPlyCount) || *count != std::floor(*count))
        throw PointFileError(path, "PLY element '" + std::string(words[1]) + "' has a bad count");
      elements.push_back({std::string(words[1]), static_cast<std::size_t>(*count), {}});
    } else if (words[0] == "property" && !elements.empty()) {
      PlyProperty property;
      if (words.size() == 5 && words[1] == "list") {
        const std::optional<ScalarType> count_type = scalar_type(words[2]);
        const std::optional<ScalarType> item_type = scalar_type(words[3]);
        if (!count_type || !item_type)
          throw PointFileError(path, "PLY list property '" + std::string(words[4]) + "' has an unknown type");
        property = {std::string(words[4]), *item_type, true, *count_type};
      } else if (words.size() == 3) {
        const std::optional<ScalarType> type = scalar_type(words[1]);
        if (!type)
          throw PointFileError(path, "PLY property '" + std::string(words[2]) + "' has unknown type '" +
                                         std::string(words[1]) + "'");
        property = {std::string(words[2]), *type, false, {}};
      } else {
        throw PointFileError(path, "bad PLY property line '" + line + "'");
      }
      elements.back().properties.push_back(property);
    } else {
      throw PointFileError(path, "unexpected PLY header line '" + line + "'");
    }
  }
  if (!header_ended)
    throw PointFileError(path, "PLY header has no end_header (truncated)");
  if (!format)
    throw PointFileError(path, "PLY header has no format line");
  const auto vertex =
      std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == elements.end())
    throw PointFileError(path, "PLY file has no vertex element");
  std::array<std::size_t, 3> xyz{};
  const std::array<std::string_view, 3> names{"x", "y", "z"};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto found =
        std::find_if(vertex->properties.begin(), vertex->properties.end(),
                     [&](const PlyProperty& p) { return p.name == names[axis] && !p.is_list; });
    if (found == vertex->properties.end())
      throw PointFileError(path, "PLY vertex element has no '" + std::string(names[axis]) + "' property");
    xyz[axis] = static_cast<std::size_t>(found - vertex->properties.begin());
  }

  PlyValues values(in, *format, path);
  LoadedCloud cloud;
  cloud.points.reserve(std::min<std::size_t>(vertex->count, std::size_t{1} << 24));  // a header may lie
  std::vector<double> row;
  for (auto element = elements.begin(); element != std::next(vertex); ++element) {
    if (element->properties.empty())
      continue;  // takes no bytes, however large its count (a loop of 2^40 empty rows would hang)
    for (std::size_t i = 0; i < element->count; ++i) {
      row.assign(element->properties.size(), 0.0);
      for (std::size_t k = 0; k < element->properties.size(); ++k) {
        const PlyProperty& property = element->properties[k];
        if (!property.is_list) {
          row[k] = values.next(property.type);
          continue;
        }
        const double items = values.next(property.count_type);  // a float type is legal, and may be anything
        if (!(items >= 0.0 && items <= kMaxPlyCount) || items != std::floor(items))
          throw PointFileError(path, "PLY list '" + property.name + "' has a bad length");
        for (std::size_t j = 0; j < static_cast<std::size_t>(items); ++j)
          static_cast<void>(values.next(property.type));
      }
      if (element == vertex)
        add_finite(cloud, {row[xyz[0]], row[xyz[1]], row[xyz[2]]});
    }
  }
  return cloud;
}

}  // namespace strata::io

#include "drivers/io/map_server_reader.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include "drivers/io/map_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

std::string_view unquoted(std::string_view s) {
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
    return s.substr(1, s.size() - 2);
  return s;
}

double number(const std::filesystem::path& path, const std::string& key, std::string_view text) {
  const std::optional<double> value = parse_number(trimmed(text));
  if (!value || !std::isfinite(*value))
    throw MapFileError(path, key + ": expected a number, got \"" + std::string(text) + "\"");
  return *value;
}

}  // namespace

// map_server's YAML is a flat list of "key: value" lines (the origin a flow sequence [x, y, yaw]); nothing in
// it needs anchors, nesting or multi-line values. A dozen lines of parsing here keep a YAML library out of
// the dependencies; a file that uses more of YAML than this fails with a message naming the line.
MapServerMetadata read_map_server_yaml(const std::filesystem::path& yaml_path) {
  std::ifstream in(yaml_path);
  if (!in)
    throw MapFileError(yaml_path, "cannot open the file");
  return read_map_server_yaml(in, yaml_path);
}

MapServerMetadata read_map_server_yaml(std::istream& in, const std::filesystem::path& yaml_path) {
  MapServerMetadata metadata;
  bool has_image = false;
  bool has_resolution = false;
  bool has_origin = false;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::string_view text = line;
    const std::size_t comment = text.find('#');
    if (comment != std::string_view::npos &&
        (comment == 0 || text[comment - 1] == ' ' || text[comment - 1] == '\t'))
      text = text.substr(0, comment);
    text = trimmed(text);
    if (text.empty() || text == "---")
      continue;
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos)
      throw MapFileError(yaml_path, "line " + std::to_string(line_number) +
                                        ": expected \"key: value\", got \"" + std::string(text) + "\"");
    const std::string key(trimmed(text.substr(0, colon)));
    const std::string_view value = unquoted(trimmed(text.substr(colon + 1)));
    if (key == "image") {
      if (value.empty())
        throw MapFileError(yaml_path, "image: empty file name");
      const std::filesystem::path image(value);
      metadata.image = image.is_absolute() ? image : yaml_path.parent_path() / image;
      has_image = true;
    } else if (key == "resolution") {
      metadata.resolution = number(yaml_path, key, value);
      if (!(metadata.resolution > 0.0))
        throw MapFileError(yaml_path, "resolution must be positive, got " + std::string(value));
      has_resolution = true;
    } else if (key == "origin") {
      if (value.size() < 2 || value.front() != '[' || value.back() != ']')
        throw MapFileError(yaml_path, "origin: expected [x, y, yaw], got \"" + std::string(value) + "\"");
      const std::vector<std::string_view> parts = split_fields(value.substr(1, value.size() - 2));
      if (parts.size() != 3 || value.find(',') == std::string_view::npos)
        throw MapFileError(yaml_path,
                           "origin: expected three numbers [x, y, yaw], got \"" + std::string(value) + "\"");
      for (int i = 0; i < 3; ++i)
        metadata.origin[i] = number(yaml_path, "origin", parts[static_cast<std::size_t>(i)]);
      has_origin = true;
    } else if (key == "negate") {
      if (value == "0" || value == "false" || value == "False")
        metadata.negate = false;
      else if (value == "1" || value == "true" || value == "True")
        metadata.negate = true;
      else
        throw MapFileError(yaml_path, "negate: expected 0 or 1, got \"" + std::string(value) + "\"");
    } else if (key == "occupied_thresh") {
      metadata.occupied_thresh = number(yaml_path, key, value);
    } else if (key == "free_thresh") {
      metadata.free_thresh = number(yaml_path, key, value);
    } else if (key == "mode") {
      metadata.mode = std::string(value);
      if (metadata.mode != "trinary" && metadata.mode != "scale" && metadata.mode != "raw")
        throw MapFileError(yaml_path, "mode: expected trinary, scale or raw, got \"" + metadata.mode + "\"");
    }
    // Other keys (e.g. Nav2's unused ones) are ignored, as map_server does.
  }
  if (!has_image || !has_resolution || !has_origin)
    throw MapFileError(yaml_path,
                       std::string("not a map_server map: missing ") + (!has_image        ? "image"
                                                                        : !has_resolution ? "resolution"
                                                                                          : "origin"));
  if (metadata.free_thresh < 0.0 || metadata.occupied_thresh > 1.0 ||
      metadata.free_thresh > metadata.occupied_thresh)
    throw MapFileError(yaml_path, "thresholds must satisfy 0 <= free_thresh <= occupied_thresh <= 1");
  return metadata;
}

namespace {

/// A PGM image's size and raw values, row 0 at the top.
struct PgmImage {
  int width = 0;
  int height = 0;
  int maxval = 0;
  std::vector<int> values;
};

PgmImage read_pgm(std::istream& in, const std::filesystem::path& path) {
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = 0;
  // Header tokens are separated by whitespace; '#' starts a comment up to the end of the line.
  const auto next_token = [&]() -> std::string {
    for (;;) {
      while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at])) != 0)
        ++at;
      if (at < bytes.size() && bytes[at] == '#') {
        while (at < bytes.size() && bytes[at] != '\n')
          ++at;
        continue;
      }
      break;
    }
    const std::size_t begin = at;
    while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at])) == 0)
      ++at;
    return bytes.substr(begin, at - begin);
  };
  const std::string magic = bytes.substr(0, 2);
  if (magic != "P5" && magic != "P2")
    throw MapFileError(path, "not a PGM image (only binary P5 and ASCII P2 grey maps are supported)");
  at = 2;
  PgmImage image;
  int* header[] = {&image.width, &image.height, &image.maxval};
  for (int* field : header) {
    const std::string token = next_token();
    const std::optional<double> value = parse_number(token);
    if (!value || *value != std::floor(*value) || *value < 1 || *value > 65535)
      throw MapFileError(
          path, "bad PGM header: expected width, height and maxval (1..65535), got \"" + token + "\"");
    *field = static_cast<int>(*value);
  }
  if (static_cast<double>(image.width) * image.height > 1e9)
    throw MapFileError(path, "the image is too large");
  const std::size_t count = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  // The pixels are allocated only once the file can hold them: a 30-byte file must not claim 4 GB (found by
  // fuzzing). In P2 every pixel but the last takes at least two bytes (a digit and a separator).
  if (magic == "P2" && (at > bytes.size() || count > (bytes.size() - at + 1) / 2))
    throw MapFileError(path, "truncated PGM: " + std::to_string(count) + " pixels cannot fit in the " +
                                 std::to_string(at > bytes.size() ? 0 : bytes.size() - at) + " bytes left");
  if (magic == "P5") {
    ++at;  // exactly one whitespace byte separates maxval from the pixels
    const std::size_t bytes_per_value = image.maxval > 255 ? 2 : 1;
    if (at > bytes.size() || bytes.size() - at < count * bytes_per_value)
      throw MapFileError(path, "truncated PGM: expected " + std::to_string(count * bytes_per_value) +
                                   " bytes of pixels, found " +
                                   std::to_string(at > bytes.size() ? 0 : bytes.size() - at));
    image.values.resize(count);
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data() + at);
    for (std::size_t i = 0; i < count; ++i)
      image.values[i] = bytes_per_value == 1 ? data[i] : (data[2 * i] << 8) | data[2 * i + 1];
  } else {
    image.values.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      const std::string token = next_token();
      const std::optional<double> value = parse_number(token);
      if (!value || *value != std::floor(*value) || *value < 0)
        throw MapFileError(path, token.empty() ? "truncated PGM: the file ends after " + std::to_string(i) +
                                                     " of " + std::to_string(count) + " pixels"
                                               : "bad PGM pixel value \"" + token + "\"");
      if (*value >
          image.maxval)  // before the cast to int, which overflows for a huge value (found by fuzzing)
        throw MapFileError(path, "pixel value " + token + " exceeds maxval " + std::to_string(image.maxval));
      image.values[i] = static_cast<int>(*value);
    }
  }
  for (const int value : image.values)
    if (value > image.maxval)
      throw MapFileError(
          path, "pixel value " + std::to_string(value) + " exceeds maxval " + std::to_string(image.maxval));
  return image;
}

void require_pgm_extension(const std::filesystem::path& image_path) {
  const std::string extension = image_path.extension().string();
  if (extension != ".pgm" && extension != ".PGM")
    throw MapFileError(image_path,
                       "only PGM map images are supported (convert it, e.g. `convert map.png map.pgm`)");
}

}  // namespace

OccupancyGrid read_map_server_image(const std::filesystem::path& image_path,
                                    const MapServerMetadata& metadata) {
  require_pgm_extension(image_path);
  std::ifstream in(image_path, std::ios::binary);
  if (!in)
    throw MapFileError(image_path, "cannot open the image");
  return read_map_server_image(in, image_path, metadata);
}

OccupancyGrid read_map_server_image(std::istream& in, const std::filesystem::path& image_path,
                                    const MapServerMetadata& metadata) {
  require_pgm_extension(image_path);
  const PgmImage image = read_pgm(in, image_path);
  OccupancyGrid grid(image.width, image.height, metadata.resolution, metadata.origin.head<2>(),
                     CellState::unknown);
  for (int row = 0; row < image.height; ++row) {
    for (int x = 0; x < image.width; ++x) {
      const int value = image.values[static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                                     static_cast<std::size_t>(x)];
      double occupancy = 0.0;
      if (metadata.mode == "raw") {
        if (value > 100)
          continue;  // stays unknown
        occupancy = value / 100.0;
      } else {
        const double shade = static_cast<double>(value) / image.maxval;
        occupancy = metadata.negate ? shade : 1.0 - shade;
      }
      CellState state = CellState::unknown;
      if (occupancy > metadata.occupied_thresh)
        state = CellState::occupied;
      else if (occupancy < metadata.free_thresh)
        state = CellState::free;
      grid.at({x, image.height - 1 - row}) = state;
    }
  }
  return grid;
}

OccupancyGrid read_map_server_map(const std::filesystem::path& yaml_path) {
  const MapServerMetadata metadata = read_map_server_yaml(yaml_path);
  return read_map_server_image(metadata.image, metadata);
}

}  // namespace strata::io

#include "drivers/io/movingai_reader.hpp"

#include <charconv>
#include <fstream>
#include <optional>
#include <string_view>

#include "drivers/io/map_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

std::ifstream open_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw MapFileError(path, "cannot open the file");
  return in;
}

std::optional<int> parse_int(std::string_view field) {
  int value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() || field.empty())
    return std::nullopt;
  return value;
}

std::optional<CellState> terrain(char c) {
  switch (c) {
    case '.':
    case 'G':
    case 'S':
      return CellState::free;
    case '@':
    case 'O':
    case 'T':
    case 'W':
      return CellState::occupied;
    default:
      return std::nullopt;
  }
}

}  // namespace

OccupancyGrid read_movingai_map(const std::filesystem::path& path) {
  std::ifstream in = open_text(path);
  return read_movingai_map(in, path);
}

OccupancyGrid read_movingai_map(std::istream& in, const std::filesystem::path& path) {
  std::string line;
  int width = -1;
  int height = -1;
  int line_number = 0;
  bool has_type = false;
  // Header: "type octile", "height H", "width W" (in any order), ended by "map".
  for (;;) {
    if (!std::getline(in, line))
      throw MapFileError(path, "not a MovingAI map: no \"map\" line ends the header");
    ++line_number;
    const std::vector<std::string_view> fields = split_fields(trimmed(line));
    if (fields.empty())
      continue;
    if (fields.size() == 1 && fields[0] == "map")
      break;
    if (fields.size() != 2)
      throw MapFileError(
          path, "line " + std::to_string(line_number) + ": expected a header line (\"type octile\", " +
                    "\"height H\", \"width W\" or \"map\"), got \"" + std::string(trimmed(line)) + "\"");
    if (fields[0] == "type") {
      if (fields[1] != "octile")
        throw MapFileError(path,
                           "map type \"" + std::string(fields[1]) + "\" is not supported (only octile)");
      has_type = true;
    } else if (fields[0] == "height" || fields[0] == "width") {
      const std::optional<int> value = parse_int(fields[1]);
      if (!value || *value <= 0)
        throw MapFileError(path, "line " + std::to_string(line_number) + ": " + std::string(fields[0]) +
                                     " must be a positive integer, got \"" + std::string(fields[1]) + "\"");
      (fields[0] == "height" ? height : width) = *value;
    } else {
      throw MapFileError(path, "line " + std::to_string(line_number) + ": unknown header key \"" +
                                   std::string(fields[0]) + "\"");
    }
  }
  if (!has_type)
    throw MapFileError(path, "not a MovingAI map: no \"type octile\" line");
  if (width < 0 || height < 0)
    throw MapFileError(path, "the header lacks \"width\" or \"height\"");

  OccupancyGrid grid(width, height);
  for (int y = 0; y < height; ++y) {
    if (!std::getline(in, line))
      throw MapFileError(path, "the header says " + std::to_string(height) +
                                   " rows but the file ends after " + std::to_string(y));
    ++line_number;
    const std::string_view row = trimmed(line);
    if (row.size() < static_cast<std::size_t>(width))
      throw MapFileError(path, "line " + std::to_string(line_number) + " (map row " + std::to_string(y) +
                                   ") has " + std::to_string(row.size()) + " cells, the header says " +
                                   std::to_string(width));
    for (int x = 0; x < width; ++x) {
      const std::optional<CellState> state = terrain(row[static_cast<std::size_t>(x)]);
      if (!state)
        throw MapFileError(path, "line " + std::to_string(line_number) + ", column " + std::to_string(x) +
                                     ": unknown terrain character '" +
                                     std::string(1, row[static_cast<std::size_t>(x)]) + "'");
      grid.at({x, y}) = *state;
    }
  }
  return grid;
}

MovingAiScenario read_movingai_scenario(const std::filesystem::path& path) {
  std::ifstream in = open_text(path);
  return read_movingai_scenario(in, path);
}

MovingAiScenario read_movingai_scenario(std::istream& in, const std::filesystem::path& path) {
  std::string line;
  if (!std::getline(in, line) || trimmed(line).substr(0, 8) != "version ")
    throw MapFileError(path, "not a MovingAI scenario: the first line is not \"version N\"");
  MovingAiScenario scenario;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> fields = split_fields(trimmed(line));
    if (fields.empty())
      continue;
    if (fields.size() != 9 || line.find(',') != std::string::npos) {
      ++scenario.skipped_lines;
      continue;
    }
    MovingAiQuery query;
    query.map = std::string(fields[1]);
    const std::optional<int> bucket = parse_int(fields[0]);
    const std::optional<int> map_width = parse_int(fields[2]);
    const std::optional<int> map_height = parse_int(fields[3]);
    const std::optional<int> sx = parse_int(fields[4]);
    const std::optional<int> sy = parse_int(fields[5]);
    const std::optional<int> gx = parse_int(fields[6]);
    const std::optional<int> gy = parse_int(fields[7]);
    const std::optional<double> length = parse_number(fields[8]);
    if (!bucket || !map_width || !map_height || !sx || !sy || !gx || !gy || !length || *length < 0.0)
      throw MapFileError(path,
                         "line " + std::to_string(line_number) +
                             ": expected bucket, map, width, height, start x, start y, goal x, goal y and a "
                             "non-negative optimal length");
    query.bucket = *bucket;
    query.map_width = *map_width;
    query.map_height = *map_height;
    query.start = {*sx, *sy};
    query.goal = {*gx, *gy};
    query.optimal_length = *length;
    scenario.queries.push_back(std::move(query));
  }
  return scenario;
}

}  // namespace strata::io

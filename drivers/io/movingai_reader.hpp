#pragma once

#include <cstddef>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "core/planning/occupancy_grid.hpp"

namespace strata::io {

/// Reads a MovingAI benchmark map ("type octile", "height H", "width W", "map", then H rows of W characters;
/// movingai.com/benchmarks/formats.html). Cell (x, y) is column x of row y, row 0 first as in the file (the
/// benchmark's own coordinates), resolution 1, origin 0. Passable: '.', 'G', 'S' (swamp); blocked: '@', 'O'
/// (out of bounds), 'T' (trees), 'W' (water). Reading stops after H rows, so text appended after the map
/// (some copies carry a BibTeX block) is ignored. Throws MapFileError.
[[nodiscard]] OccupancyGrid read_movingai_map(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] OccupancyGrid read_movingai_map(std::istream& in, const std::filesystem::path& source);

/// One query of a MovingAI scenario: the optimal length of the path from start to goal (8-connected,
/// diagonal sqrt 2, no corner cutting). Length 0 with start != goal marks a goal with no path.
struct MovingAiQuery {
  int bucket = 0;
  std::string map;
  int map_width = 0;
  int map_height = 0;
  GridCell start;
  GridCell goal;
  double optimal_length = 0.0;
};

struct MovingAiScenario {
  std::vector<MovingAiQuery> queries;
  std::size_t skipped_lines = 0;  ///< non-blank lines without 9 fields (e.g. an appended BibTeX block)
};

/// Reads a MovingAI .scen file ("version N", then one query per line: bucket, map, map width, map height,
/// start x, start y, goal x, goal y, optimal length; tabs or spaces). Lines without exactly 9 fields are
/// skipped and counted; a 9-field line whose numbers do not parse is an error. Throws MapFileError.
[[nodiscard]] MovingAiScenario read_movingai_scenario(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] MovingAiScenario read_movingai_scenario(std::istream& in, const std::filesystem::path& source);

}  // namespace strata::io

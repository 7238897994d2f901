#include "drivers/io/xyz_reader.hpp"

#include <array>
#include <fstream>
#include <string>

#include "drivers/io/point_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {

LoadedCloud read_xyz(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_xyz(in, path);
}

LoadedCloud read_xyz(std::istream& in, const std::filesystem::path& path) {
  std::array<std::size_t, 3> columns{0, 1, 2};
  bool first_row = true;
  LoadedCloud cloud;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.empty() || fields[0].starts_with('#'))
      continue;
    if (first_row) {
      first_row = false;
      if (!parse_number(fields[0])) {  // a header: find the named columns
        const std::array<std::string_view, 3> names{"x", "y", "z"};
        for (std::size_t axis = 0; axis < 3; ++axis) {
          std::size_t k = 0;
          while (k < fields.size() && fields[k] != names[axis])
            ++k;
          if (k == fields.size())
            throw PointFileError(path,
                                 "header '" + line + "' has no '" + std::string(names[axis]) + "' column");
          columns[axis] = k;
        }
        continue;
      }
    }
    Eigen::Vector3d p;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      if (columns[axis] >= fields.size())
        throw PointFileError(path, "line " + std::to_string(line_number) + " has " +
                                       std::to_string(fields.size()) + " columns, needs " +
                                       std::to_string(columns[axis] + 1));
      const std::optional<double> value = parse_number(fields[columns[axis]]);
      if (!value)
        throw PointFileError(path, "line " + std::to_string(line_number) + ": '" +
                                       std::string(fields[columns[axis]]) + "' is not a number");
      p[static_cast<Eigen::Index>(axis)] = *value;
    }
    add_finite(cloud, p);
  }
  if (in.bad())
    throw PointFileError(path, "read error");
  return cloud;
}

}  // namespace strata::io

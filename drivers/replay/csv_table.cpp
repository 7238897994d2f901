#include "drivers/replay/csv_table.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "drivers/io/text_fields.hpp"
#include "drivers/replay/dataset.hpp"

namespace strata::replay {

CsvTable::CsvTable(std::istream& in, std::string source) : source_(std::move(source)) {
  std::string line;
  if (!std::getline(in, line))
    throw DatasetError(source_ + ": empty (expected a header row)");
  for (const std::string_view name : io::split_fields(line))
    columns_.emplace_back(name);
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (io::trimmed(line).empty())
      continue;
    std::vector<std::string> row;
    for (const std::string_view field : io::split_fields(line))
      row.emplace_back(field);
    if (row.size() != columns_.size()) {
      throw DatasetError(fmt::format("{}: line {} has {} fields, the header {}", source_, number, row.size(),
                                     columns_.size()));
    }
    rows_.push_back(std::move(row));
    lines_.push_back(number);
  }
}

const std::string& CsvTable::text(std::size_t row, const std::string& column) const {
  const auto i = index(column);
  if (!i)
    throw DatasetError(source_ + ": no column '" + column + "'");
  return rows_[row][*i];
}

double CsvTable::number(std::size_t row, const std::string& column) const {
  const std::string& field = text(row, column);
  const auto value = io::parse_number(field);
  if (!value || !std::isfinite(*value))
    throw DatasetError(
        fmt::format("{}: line {}: {} '{}' is not a number", source_, lines_[row], column, field));
  return *value;
}

std::optional<Pose3> CsvTable::pose(std::size_t row, const std::string& prefix) const {
  static const char* const kNames[] = {"x", "y", "z", "roll", "pitch", "yaw"};
  if (!has(prefix + "x"))
    return std::nullopt;
  if (text(row, prefix + "x").empty())
    return std::nullopt;
  double values[6];
  for (std::size_t i = 0; i < 6; ++i)
    values[i] = number(row, prefix + kNames[i]);
  Pose3 pose;
  pose.position = Eigen::Vector3d(values[0], values[1], values[2]);
  pose.roll = values[3];
  pose.pitch = values[4];
  pose.yaw = values[5];
  return pose;
}

std::optional<std::size_t> CsvTable::index(const std::string& column) const {
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  if (it == columns_.end())
    return std::nullopt;
  return static_cast<std::size_t>(it - columns_.begin());
}

}  // namespace strata::replay

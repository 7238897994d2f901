#pragma once

#include <cstddef>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace strata::replay {

/// The rows of a CSV file with a header row (a replay's scans.csv and odometry.csv), each as column name ->
/// field. Errors name the source and the line; they are DatasetErrors.
class CsvTable {
 public:
  /// Reads every row; `source` names the text in errors (the file's path). Throws DatasetError for a text
  /// without a header row or a row whose field count differs from the header's.
  CsvTable(std::istream& in, std::string source);

  [[nodiscard]] std::size_t size() const { return rows_.size(); }
  [[nodiscard]] bool has(const std::string& column) const { return index(column).has_value(); }
  /// The field as text; throws when the column is missing.
  [[nodiscard]] const std::string& text(std::size_t row, const std::string& column) const;
  /// The field as a finite number; throws naming the line otherwise.
  [[nodiscard]] double number(std::size_t row, const std::string& column) const;
  /// The pose in columns prefix+x ... prefix+yaw: nothing when the columns are missing or all empty.
  [[nodiscard]] std::optional<Pose3> pose(std::size_t row, const std::string& prefix) const;

 private:
  [[nodiscard]] std::optional<std::size_t> index(const std::string& column) const;

  std::string source_;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<std::size_t> lines_;
};

}  // namespace strata::replay

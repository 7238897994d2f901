#pragma once

#include <charconv>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace strata::io {

/// `s` without blanks (spaces, tabs) around it, nor a trailing carriage return (files from Windows).
[[nodiscard]] inline std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  return s;
}

/// Splits a line into fields: on commas if it has any (CSV; blanks around fields are trimmed), otherwise on
/// whitespace.
[[nodiscard]] inline std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  const bool csv = line.find(',') != std::string_view::npos;
  const auto is_blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  std::size_t i = 0;
  while (i <= line.size()) {
    if (csv) {
      std::size_t end = line.find(',', i);
      if (end == std::string_view::npos)
        end = line.size();
      std::string_view field = line.substr(i, end - i);
      while (!field.empty() && is_blank(field.front()))
        field.remove_prefix(1);
      while (!field.empty() && is_blank(field.back()))
        field.remove_suffix(1);
      fields.push_back(field);
      i = end + 1;
    } else {
      while (i < line.size() && is_blank(line[i]))
        ++i;
      if (i >= line.size())
        break;
      std::size_t end = i;
      while (end < line.size() && !is_blank(line[end]))
        ++end;
      fields.push_back(line.substr(i, end - i));
      i = end;
    }
  }
  return fields;
}

/// The whole field as a number ("nan" and "inf" included), or empty if it is not one.
[[nodiscard]] inline std::optional<double> parse_number(std::string_view field) {
  if (!field.empty() && field.front() == '+')
    field.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() || field.empty())
    return std::nullopt;
  return value;
}

}  // namespace strata::io

#include "server/api/static_files.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <system_error>
#include <utility>

namespace strata::api {

std::optional<std::filesystem::path> resolve_static_path(const std::filesystem::path& root,
                                                         std::string_view request_path) {
  if (request_path.empty() || request_path.front() != '/')
    return std::nullopt;
  // Refuse anything but plain names: no escapes, no encodings to decode wrongly.
  constexpr std::string_view kForbidden{"\\%\0:", 4};
  if (request_path.find_first_of(kForbidden) != std::string_view::npos)
    return std::nullopt;

  std::filesystem::path relative;
  std::size_t start = 1;
  while (start <= request_path.size()) {
    const std::size_t end = std::min(request_path.find('/', start), request_path.size());
    const std::string_view segment = request_path.substr(start, end - start);
    if (segment == "..")
      return std::nullopt;
    if (!segment.empty() && segment != ".")
      relative /= std::string(segment);
    start = end + 1;
  }

  std::filesystem::path file = root / relative;
  std::error_code error;
  if (std::filesystem::is_directory(file, error))
    file /= "index.html";
  if (!std::filesystem::is_regular_file(file, error))
    return std::nullopt;
  return file;
}

std::string_view mime_type(const std::filesystem::path& file) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 14> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".wasm", "application/wasm"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".svg", "image/svg+xml"},
      {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},
      {".map", "application/json"},
      {".woff2", "font/woff2"},
      {".drc", "application/octet-stream"},
  }};
  const std::string extension = file.extension().string();
  for (const auto& [ext, type] : kTypes) {
    if (ext == extension)
      return type;
  }
  return "application/octet-stream";
}

}  // namespace strata::api

#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace strata::io {

/// A map or scenario file that cannot be read: names the file and what is wrong with it.
class MapFileError : public std::runtime_error {
 public:
  MapFileError(const std::filesystem::path& path, const std::string& problem)
      : std::runtime_error(path.string() + ": " + problem), path_(path) {}
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace strata::io

#include "server/pipeline/file_bytes.hpp"

#include <fstream>
#include <iterator>

namespace strata::pipeline {

std::optional<std::string> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream)
    return std::nullopt;
  std::string bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
  if (stream.bad())
    return std::nullopt;
  return bytes;
}

}  // namespace strata::pipeline

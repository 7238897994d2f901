#include "drivers/ros2/cdr_reader.hpp"

namespace strata::ros2 {
CdrReader::CdrReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {
  if (bytes.size() < kEncapsulationHeader || bytes[0] != 0x00 || bytes[1] != 0x01)
    throw CdrError("not a little-endian CDR message (no CDR_LE encapsulation header)");
}

void CdrReader::align(std::size_t size) {
  const std::size_t offset = position_ - kEncapsulationHeader;
  const std::size_t padding = (size - offset % size) % size;
  take(padding);
}

std::span<const std::uint8_t> CdrReader::take(std::size_t size) {
  if (size > bytes_.size() - position_)
    throw CdrError("the CDR message ends before its fields do");
  const auto taken = bytes_.subspan(position_, size);
  position_ += size;
  return taken;
}

std::string CdrReader::read_string() {
  const std::uint32_t size = read<std::uint32_t>();  // with the closing NUL
  if (size == 0)
    return {};
  const auto bytes = take(size);
  if (bytes.back() != 0)
    throw CdrError("a CDR string without its closing NUL");
  return {reinterpret_cast<const char*>(bytes.data()), size - 1};
}

}  // namespace strata::ros2

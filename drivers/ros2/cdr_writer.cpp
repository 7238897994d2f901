#include "drivers/ros2/cdr_writer.hpp"

#include <bit>
#include <limits>
#include <stdexcept>

namespace strata::ros2 {
namespace {

static_assert(std::endian::native == std::endian::little, "CdrWriter writes the host's byte order as CDR_LE");

std::uint32_t checked_size(std::size_t count) {
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("a CDR sequence or string holds at most 2^32 - 1 elements");
  return static_cast<std::uint32_t>(count);
}

}  // namespace

CdrWriter::CdrWriter() : bytes_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::align(std::size_t size) {
  const std::size_t offset = bytes_.size() - kEncapsulationHeader;
  bytes_.resize(bytes_.size() + (size - offset % size) % size, 0);
}

void CdrWriter::write_string(std::string_view text) {
  write(checked_size(text.size() + 1));
  bytes_.insert(bytes_.end(), text.begin(), text.end());
  bytes_.push_back(0);
}

void CdrWriter::write_sequence_size(std::size_t count) {
  write(checked_size(count));
}

void CdrWriter::write_byte_sequence(std::span<const std::uint8_t> data) {
  write_sequence_size(data.size());
  bytes_.insert(bytes_.end(), data.begin(), data.end());
}

void CdrWriter::write_doubles(std::span<const double> values) {
  for (const double value : values)
    write(value);
}

}  // namespace strata::ros2

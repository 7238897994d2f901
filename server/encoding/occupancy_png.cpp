#include "server/encoding/occupancy_png.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

namespace strata::encoding {
namespace {

std::uint8_t grey_of(Occupancy occupancy) {
  switch (occupancy) {
    case Occupancy::free:
      return kPngFree;
    case Occupancy::occupied:
      return kPngOccupied;
    case Occupancy::unknown:
      break;
  }
  return kPngUnknown;
}

}  // namespace

EncodedOccupancy encode_occupancy_png(const LevelGrid& grid, double level_z, std::uint64_t version) {
  EncodedOccupancy encoded;
  encoded.version = version;
  encoded.origin_x = grid.origin.x();
  encoded.origin_y = grid.origin.y();
  encoded.resolution = grid.resolution;
  encoded.width = grid.width;
  encoded.height = grid.height;
  encoded.level_z = level_z;
  if (grid.width <= 0 || grid.height <= 0)
    return encoded;
  cv::Mat image(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row) {
    // Image rows run down, grid rows up (row 0 at the lowest y).
    auto* out = image.ptr<std::uint8_t>(grid.height - 1 - row);
    for (int col = 0; col < grid.width; ++col)
      out[col] = grey_of(grid.at(col, row));
  }
  // Level 1 of 9: the occupancy is mostly long runs, which the fastest deflate already catches; the
  // mapping thread pays for every level above.
  if (!cv::imencode(".png", image, encoded.png, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    throw OccupancyPngError("occupancy: the PNG encoder failed");
  return encoded;
}

LevelGrid decode_occupancy_png(const EncodedOccupancy& encoded) {
  LevelGrid grid;
  grid.origin = {encoded.origin_x, encoded.origin_y};
  grid.resolution = encoded.resolution;
  grid.width = encoded.width;
  grid.height = encoded.height;
  if (encoded.png.empty()) {
    if (encoded.width != 0 || encoded.height != 0)
      throw OccupancyPngError("occupancy: no PNG for a " + std::to_string(encoded.width) + " x " +
                              std::to_string(encoded.height) + " grid");
    return grid;
  }
  const cv::Mat image = cv::imdecode(encoded.png, cv::IMREAD_UNCHANGED);
  if (image.empty() || image.type() != CV_8UC1)
    throw OccupancyPngError("occupancy: not an 8-bit grey PNG");
  if (image.cols != encoded.width || image.rows != encoded.height)
    throw OccupancyPngError("occupancy: the PNG is " + std::to_string(image.cols) + " x " +
                            std::to_string(image.rows) + ", the placement says " +
                            std::to_string(encoded.width) + " x " + std::to_string(encoded.height));
  grid.cells.resize(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height));
  for (int row = 0; row < grid.height; ++row) {
    const auto* in = image.ptr<std::uint8_t>(grid.height - 1 - row);
    for (int col = 0; col < grid.width; ++col) {
      Occupancy& cell = grid.cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.width) +
                                   static_cast<std::size_t>(col)];
      switch (in[col]) {
        case kPngFree:
          cell = Occupancy::free;
          break;
        case kPngOccupied:
          cell = Occupancy::occupied;
          break;
        case kPngUnknown:
          cell = Occupancy::unknown;
          break;
        default:
          throw OccupancyPngError("occupancy: grey value " + std::to_string(in[col]) +
                                  " is none of free, occupied, unknown");
      }
    }
  }
  return grid;
}

}  // namespace strata::encoding

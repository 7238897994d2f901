#include "server/encoding/occupancy_png.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace strata::encoding {
namespace {

LevelGrid asymmetric_grid() {
  LevelGrid grid;
  grid.origin = {-3.2, 1.5};
  grid.resolution = 0.1;
  grid.width = 5;
  grid.height = 3;
  grid.cells.assign(15, Occupancy::unknown);
  grid.surface_height.assign(15, 0.0F);
  grid.cells[0] = Occupancy::free;       // (0, 0): lowest y, first column
  grid.cells[1] = Occupancy::occupied;   // (1, 0)
  grid.cells[14] = Occupancy::occupied;  // (4, 2): highest y, last column
  grid.cells[7] = Occupancy::free;       // (2, 1)
  return grid;
}

TEST(OccupancyPng, ImageRowZeroIsTheHighestYWithMapServerGreys) {
  const EncodedOccupancy encoded = encode_occupancy_png(asymmetric_grid(), 0.42, 7);
  EXPECT_EQ(encoded.version, 7U);
  EXPECT_DOUBLE_EQ(encoded.origin_x, -3.2);
  EXPECT_DOUBLE_EQ(encoded.origin_y, 1.5);
  EXPECT_DOUBLE_EQ(encoded.resolution, 0.1);
  EXPECT_DOUBLE_EQ(encoded.level_z, 0.42);
  EXPECT_EQ(encoded.width, 5);
  EXPECT_EQ(encoded.height, 3);
  ASSERT_GT(encoded.png.size(), 8U);
  EXPECT_EQ(encoded.png[1], 'P');  // \x89PNG
  const cv::Mat image = cv::imdecode(encoded.png, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8UC1);
  EXPECT_EQ(image.at<std::uint8_t>(2, 0), kPngFree);      // grid (0, 0) is the bottom image row
  EXPECT_EQ(image.at<std::uint8_t>(2, 1), kPngOccupied);  // grid (1, 0)
  EXPECT_EQ(image.at<std::uint8_t>(0, 4), kPngOccupied);  // grid (4, 2) is the top image row
  EXPECT_EQ(image.at<std::uint8_t>(1, 2), kPngFree);      // grid (2, 1)
  EXPECT_EQ(image.at<std::uint8_t>(0, 0), kPngUnknown);
}

TEST(OccupancyPng, DecodesBackToTheSameGrid) {
  const LevelGrid grid = asymmetric_grid();
  const LevelGrid decoded = decode_occupancy_png(encode_occupancy_png(grid, 0.0, 1));
  EXPECT_EQ(decoded.cells, grid.cells);
  EXPECT_EQ(decoded.origin, grid.origin);
  EXPECT_EQ(decoded.width, grid.width);
  EXPECT_EQ(decoded.height, grid.height);
}

TEST(OccupancyPng, EmptyGridHasNoImage) {
  const EncodedOccupancy encoded = encode_occupancy_png(LevelGrid{}, 0.0, 1);
  EXPECT_TRUE(encoded.png.empty());
  EXPECT_TRUE(decode_occupancy_png(encoded).cells.empty());
}

TEST(OccupancyPng, BadImagesGiveACleanError) {
  EncodedOccupancy encoded = encode_occupancy_png(asymmetric_grid(), 0.0, 1);
  EncodedOccupancy wrong_size = encoded;
  wrong_size.width = 6;
  EXPECT_THROW(static_cast<void>(decode_occupancy_png(wrong_size)), OccupancyPngError);
  EncodedOccupancy truncated = encoded;
  truncated.png.resize(truncated.png.size() / 2);
  EXPECT_THROW(static_cast<void>(decode_occupancy_png(truncated)), OccupancyPngError);
  EncodedOccupancy missing = encoded;
  missing.png.clear();
  EXPECT_THROW(static_cast<void>(decode_occupancy_png(missing)), OccupancyPngError);
}

}  // namespace
}  // namespace strata::encoding

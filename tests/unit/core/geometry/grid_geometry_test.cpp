#include "core/geometry/grid_geometry.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace strata {
namespace {

TEST(GridGeometry, CellsAreHalfOpenSquaresFromTheOrigin) {
  const GridGeometry grid{{-1.0, 2.0}, 0.5, 4, 3};
  EXPECT_EQ(grid.cell_count(), 12U);
  EXPECT_EQ(grid.cell_of({-1.0, 2.0}), (GridCell{0, 0}));
  EXPECT_EQ(grid.cell_of({-0.5, 2.49}), (GridCell{1, 0}));  // the lower edge belongs to the cell
  EXPECT_EQ(grid.cell_of({-1.01, 1.99}), (GridCell{-1, -1}));
  EXPECT_EQ(grid.index({3, 2}), 11U);
  EXPECT_TRUE(grid.center_of({1, 2}).isApprox(Eigen::Vector2d(-0.25, 3.25)));
  EXPECT_EQ(grid.cell_of(grid.center_of({3, 1})), (GridCell{3, 1}));
}

TEST(GridGeometry, FarAndNotANumberPointsAreOutside) {
  const GridGeometry grid{{0.0, 0.0}, 0.1, 10, 10};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector2d& point : {Eigen::Vector2d(1e300, 0.5), Eigen::Vector2d(-1e300, 0.5),
                                       Eigen::Vector2d(nan, 0.5), Eigen::Vector2d(0.5, nan)})
    EXPECT_FALSE(grid.contains(grid.cell_of(point))) << point.transpose();
}

}  // namespace
}  // namespace strata

#include <gtest/gtest.h>

#include <filesystem>

#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"
#include "drivers/io/threedtk_reader.hpp"

namespace strata {
namespace {

namespace fs = std::filesystem;

// The three 3DTK example scans (outdoor, stop-and-go, sensor about 0.5 m above the ground) with slam6D's
// registered poses. Skipped when the shared data is absent.
TEST(MlsRealData, ThreeDtkScansGiveDrivableGroundAndWalls) {
  const fs::path dir = fs::path(STRATA_DATA_DIR) / "3dtk_dat";
  if (!fs::exists(dir / "scan000.3d") || !fs::exists(dir / "reference_slam6d_2009/scan000.frames"))
    GTEST_SKIP() << "no 3DTK scans in " << dir << " (set STRATA_DATA_DIR)";
  MlsMap map;
  Eigen::Vector3d first_origin = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const std::string name = "scan00" + std::to_string(i);
    const Eigen::Isometry3d pose = io::read_3dtk_frames(dir / "reference_slam6d_2009" / (name + ".frames"));
    const PointCloud points = transformed(io::read_3dtk_scan(dir / (name + ".3d")).points, pose);
    map.insert_scan(points, pose.translation());
    if (i == 0)
      first_origin = pose.translation();
  }
  std::size_t vertical = 0;
  for (const TileIndex& tile_index : map.tile_indices())
    for (int local = 0; local < kMlsTileCells; ++local)
      map.find_tile(tile_index)->for_each_patch(local, [&](const MlsPatch& p) {
        if (p.vertical() && p.depth > 1.0F)
          ++vertical;
      });
  EXPECT_GT(vertical, 200U) << "walls and trees reach metres high";

  // The ground about 0.45 m below the sensor, 1.5 m ahead (x forward): the scanner does not see the
  // first metre around itself, which leaves a strip of unknown cells the fill cannot cross.
  const Eigen::Vector3d ground = first_origin + Eigen::Vector3d(1.5, 0, -0.45);
  const CellIndex robot = map.cell_of(ground.x(), ground.y());
  const CellRegion region{{robot.x - 200, robot.y - 200}, 400, 400};
  // The outdoor ground here is rough (curbs, and 5-10 cm seams where the scans' grounds meet), so the
  // robot is allowed the wheelchair's highest step, 0.1 m.
  TraversabilityConfig wheelchair;
  wheelchair.max_step = 0.1;
  const DrivableMap drivable = compute_drivable_map(map, wheelchair, ground, region);
  ASSERT_TRUE(drivable.start_found) << "no ground patch near the first scan's sensor";
  EXPECT_GT(drivable.free_cells, 300U) << "at least 3 m^2 of drivable ground";
  std::size_t occupied = 0;
  for (const Occupancy o : drivable.grid.cells)
    occupied += o == Occupancy::occupied ? 1U : 0U;
  EXPECT_GT(occupied, 500U);
}

}  // namespace
}  // namespace strata

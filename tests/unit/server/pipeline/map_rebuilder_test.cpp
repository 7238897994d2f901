#include "server/pipeline/map_rebuilder.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/wall_keyframes.hpp"

namespace strata::pipeline {
namespace {

using strata::testing::room_keyframe;

Eigen::Isometry3d shifted(double x) {
  return Eigen::Isometry3d(Eigen::Translation3d(x, 0.0, 0.0));
}

/// Patches in the column of cells at `x` (all y of the room).
std::size_t patches_at_x(const MlsMap& map, double x) {
  std::size_t patches = 0;
  for (double y = -1.5; y <= 1.5; y += map.resolution())
    patches += map.patches(map.cell_of(x, y)).size();
  return patches;
}

TEST(MapRebuilder, NothingIsDueUntilAKeyframeMovesByHalfACell) {
  const MapRebuilder rebuilder(MlsConfig{});
  const KeyframePtr first = room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  const KeyframePtr second = room_keyframe(shifted(0.3), 2.0);
  EXPECT_EQ(rebuilder.moves({{first, first->mapped_pose}, {second, second->mapped_pose}}).moved, 0U);
  EXPECT_EQ(rebuilder.moves({{first, first->mapped_pose}, {second, shifted(0.28)}}).moved, 0U)
      << "2 cm is less than half a 10 cm cell";
  const KeyframeMoves moves =
      rebuilder.moves({{first, first->mapped_pose}, {second, Eigen::Isometry3d::Identity()}});
  EXPECT_EQ(moves.moved, 1U);
  EXPECT_NEAR(moves.largest_shift, 0.3, 1e-9);
  const Eigen::Isometry3d turned(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(rebuilder.moves({{first, turned}}).moved, 1U) << "0.01 rad moves a wall 10 m away by 10 cm";
}

TEST(MapRebuilder, TheRebuiltMapHasOneWallWhereTheLiveMapHadTwo) {
  // The second visit drifted 0.3 m: the live map would have the wall at 3.0 and at 3.3 m. The pose graph
  // found it was at the origin too.
  const KeyframePtr first = room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  const KeyframePtr second = room_keyframe(shifted(0.3), 2.0);
  const std::vector<KeyframePose> corrected{{first, Eigen::Isometry3d::Identity()},
                                            {second, Eigen::Isometry3d::Identity()}};
  MapRebuilder rebuilder(MlsConfig{});
  const MlsMap map = rebuilder.build(corrected);
  EXPECT_GT(patches_at_x(map, 3.0), 0U);
  EXPECT_EQ(patches_at_x(map, 3.3), 0U);
  EXPECT_GT(patches_at_x(map, 1.0), 0U) << "the floor";
  // Built from the keyframes, not the drift: the same map as two visits from the same place.
  const MlsMap once = rebuilder.build({{first, Eigen::Isometry3d::Identity()}});
  EXPECT_EQ(map.occupied_cell_count(), once.occupied_cell_count());

  EXPECT_EQ(rebuilder.moves(corrected).moved, 1U);
  rebuilder.landed(corrected);
  EXPECT_EQ(rebuilder.moves(corrected).moved, 0U) << "the map has them where they are now";
}

TEST(MapRebuilder, TheGroundTheRobotDroveIsMarkedWhereTheKeyframesAreNow) {
  // The robot stood at each keyframe's base origin: that ground goes into the rebuilt map at the corrected
  // pose, so the robot is never left on a map without ground under it after a rebuild.
  const KeyframePtr first = room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  const KeyframePtr second = room_keyframe(shifted(0.3), 2.0);
  const MlsMap map =
      MapRebuilder(MlsConfig{}).build({{first, Eigen::Isometry3d::Identity()}, {second, shifted(-1.0)}});
  const auto driven_at = [&](double x) {
    const std::vector<MlsPatch> patches = map.patches(map.cell_of(x, 0.05));
    return std::ranges::any_of(patches, [](const MlsPatch& p) { return p.driven(); });
  };
  EXPECT_TRUE(driven_at(0.05));
  EXPECT_TRUE(driven_at(-0.95));
  EXPECT_FALSE(driven_at(0.35)) << "where the drifted pose had it";
}

TEST(MapRebuilder, TheWholeTrackBetweenKeyframesIsDriven) {
  // A lidar's keyframe comes every metre and holds the scans since the last one: the rebuilt map has the
  // ground of each, not only of the keyframe's own spot (the robot must be able to drive back along it).
  auto keyframe = std::make_shared<Keyframe>();
  keyframe->stamp = 1.0;
  for (const float x : {-1.0F, -0.6F, -0.2F, 0.0F}) {
    KeyframeScan scan;
    scan.ground = Eigen::Vector3f(x, 0.0F, 0.0F);
    scan.sensor_origin = Eigen::Vector3f(x, 0.0F, 1.0F);
    scan.points.emplace_back(x + 3.0F, 0.0F, 0.0F);  // a lidar sees the ground metres ahead, not below
    keyframe->scans.push_back(scan);
  }
  const MlsMap map = MapRebuilder(MlsConfig{}).build({{keyframe, shifted(2.0)}});
  for (double x = 0.95; x <= 2.05; x += 0.1) {
    const std::vector<MlsPatch> patches = map.patches(map.cell_of(x, 0.05));
    EXPECT_TRUE(std::ranges::any_of(patches, [](const MlsPatch& p) { return p.driven(); })) << "x = " << x;
  }
}

}  // namespace
}  // namespace strata::pipeline

#include "core/registration/surface_sides.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/ann/kdtree.hpp"
#include "core/registration/icp.hpp"

namespace strata {
namespace {

constexpr double kThickness = 0.2;  // thinner than the fine correspondence bound, 0.25 m

/// Two rooms on either side of a wall 0.2 m thick, across y. The map (target) was made in the room at
/// y < 0, from (0, -2, 1): the wall's face there, at y = 0, and the floor of both rooms (the other's seen
/// through a door). The scan (source) is taken from (0, 2, 1) in the other room, at the true pose: its
/// floor and the wall's other face, at y = 0.2. Nothing but the wall tells y or the turn about z.
struct ThinWall {
  PointCloud target;
  std::vector<Eigen::Vector3d> target_viewpoints;
  PointCloud source;
  PointCloud source_floor;
  Eigen::Vector3d source_viewpoint{0.0, 2.0, 1.0};
};

ThinWall thin_wall() {
  ThinWall scene;
  for (double x = -4.0; x <= 4.0; x += 0.05) {
    for (double z = 0.3; z <= 2.0; z += 0.05) {
      scene.target.emplace_back(x, 0.0, z);
      scene.source.emplace_back(x, kThickness, z);
    }
    for (double y = -3.0; y <= 3.0; y += 0.05)
      scene.target.emplace_back(x + 0.025, y + 0.025, 0.0);
    for (double y = kThickness + 0.05; y <= 3.0; y += 0.05)
      scene.source_floor.emplace_back(x, y, 0.0);
  }
  scene.source.insert(scene.source.end(), scene.source_floor.begin(), scene.source_floor.end());
  scene.target_viewpoints.assign(scene.target.size(), Eigen::Vector3d(0.0, -2.0, 1.0));
  return scene;
}

IcpOptions fine_point_to_plane() {
  IcpOptions options;
  options.metric = IcpMetric::kPointToPlane;
  options.max_correspondence_distance = 0.25;
  options.max_iterations = 50;
  options.min_step_translation = 1e-5;
  options.min_step_rotation = 1e-6;
  return options;
}

double yaw_of(const Eigen::Isometry3d& transform) {
  return std::atan2(transform.linear()(1, 0), transform.linear()(0, 0));
}

// Without the viewpoints the scan's face pairs with the map's other face and is pulled the wall's
// thickness through it; with them those pairs tell the wall's turn, not where it is.
TEST(SurfaceSides, PairsAcrossAThinWallDoNotPullTheScanThroughIt) {
  const ThinWall scene = thin_wall();
  const GrowingKdTree target(scene.target);
  const SurfaceSides sides{.target_viewpoints = &scene.target_viewpoints,
                           .source_viewpoint = scene.source_viewpoint};
  const IcpOptions options = fine_point_to_plane();

  LazyNormals blind_normals(target);
  const IcpResult blind = align(scene.source, target, &blind_normals, Eigen::Isometry3d::Identity(), options);
  EXPECT_LT(blind.transform.translation().y(), -0.15) << "the other face's pull";

  LazyNormals normals(target);
  const IcpResult result =
      align(scene.source, target, &normals, Eigen::Isometry3d::Identity(), options, &sides);
  EXPECT_NEAR(result.transform.translation().y(), 0.0, 0.005);
  EXPECT_FALSE(result.pairs.empty());  // the floor's
  for (const Correspondence& pair : result.pairs)
    EXPECT_NEAR(scene.target[pair.target].z(), 0.0, 1e-9) << "no pair with the wall's other face is kept";
}

// The scan turned half a degree: the wall's pairs, each wall's offset left free, still turn it back, and
// do not pull it through the wall; the floor alone could not turn it.
TEST(SurfaceSides, AThinWallsOtherFaceStillTellsTheTurn) {
  const ThinWall scene = thin_wall();
  const GrowingKdTree target(scene.target);
  const SurfaceSides sides{.target_viewpoints = &scene.target_viewpoints,
                           .source_viewpoint = scene.source_viewpoint};
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  guess.linear() =
      Eigen::AngleAxisd(0.5 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  LazyNormals normals(target);
  const IcpResult result = align(scene.source, target, &normals, guess, fine_point_to_plane(), &sides);
  EXPECT_LT(std::abs(yaw_of(result.transform)), 0.02 * std::numbers::pi / 180.0);
  EXPECT_NEAR(result.transform.translation().y(), 0.0, 0.005);

  LazyNormals floor_normals(target);
  const IcpResult floor_only =
      align(scene.source_floor, target, &floor_normals, guess, fine_point_to_plane(), &sides);
  EXPECT_GT(std::abs(yaw_of(floor_only.transform)), 0.45 * std::numbers::pi / 180.0)
      << "the floor tells no turn";
}

// A pair is across only where both sides are sure: a viewpoint near the surface's plane, where the
// normal's error could put it on either side, keeps its pairs.
TEST(SurfaceSides, AViewpointNearThePlaneIsNoSide) {
  PointCloud grid;
  for (double x = -0.2; x <= 0.2; x += 0.05)
    for (double z = -0.2; z <= 0.2; z += 0.05)
      grid.emplace_back(x, 0.0, z);
  const GrowingKdTree tree(grid);
  LazyNormals normals(tree);
  std::vector<Eigen::Vector3d> viewpoints(grid.size(), Eigen::Vector3d(0.0, -2.0, 0.0));
  const SurfaceSides sides{.target_viewpoints = &viewpoints, .source_viewpoint = {0.0, 0.04, 0.0}};
  std::vector<Correspondence> pairs{{0, 0}};
  std::vector<AcrossPair> across;
  split_across(Eigen::Isometry3d::Identity(), grid, normals, sides, {}, pairs, across);
  EXPECT_EQ(pairs.size(), 1U) << "4 cm off the plane: under the 5 cm margin";
  EXPECT_TRUE(across.empty());

  const SurfaceSides far_side{.target_viewpoints = &viewpoints, .source_viewpoint = {0.0, 2.0, 0.0}};
  split_across(Eigen::Isometry3d::Identity(), grid, normals, far_side, {}, pairs, across);
  EXPECT_TRUE(pairs.empty());
  ASSERT_EQ(across.size(), 1U);

  std::vector<Eigen::Vector3d> too_few(grid.size() - 1, Eigen::Vector3d(0.0, -2.0, 0.0));
  const SurfaceSides mismatched{.target_viewpoints = &too_few, .source_viewpoint = {0.0, 2.0, 0.0}};
  pairs = {{0, 0}};
  split_across(Eigen::Isometry3d::Identity(), grid, normals, mismatched, {}, pairs, across);
  EXPECT_EQ(pairs.size(), 1U) << "viewpoints that do not match the target tell nothing";
}

}  // namespace
}  // namespace strata

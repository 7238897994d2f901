#include "core/registration/icp.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>

#include "core/registration/register_scan.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

using test::make_transform;
using test::rotation_error;
using test::translation_error;

// The target is the room; the source is the room seen from a moved sensor: target points mapped by the
// inverse of the true source->target transform, re-sampled with other noise.
struct Scene {
  PointCloud source;
  PointCloud target;
  Eigen::Isometry3d truth;
};

Scene moved_room(const Eigen::Isometry3d& truth, double step = 0.1) {
  return {transformed(test::room_scene(step, 0.005, 11), truth.inverse()), test::room_scene(step, 0.005, 12),
          truth};
}

class IcpRecovers : public testing::TestWithParam<std::tuple<IcpMetric, RotationSolver, double>> {};

TEST_P(IcpRecovers, KnownTransformFromANearbyGuess) {
  const auto [metric, solver, kernel] = GetParam();
  const Scene scene = moved_room(make_transform(0.4, -0.3, 0.05, 0.03, -0.02, 0.15));
  const GrowingKdTree target(scene.target);
  LazyNormals normals(target);
  IcpOptions options;
  options.metric = metric;
  options.rotation_solver = solver;
  options.kernel_scale = kernel;
  options.max_iterations = 100;
  options.mse_change_threshold = 1e-10;
  // Coarse bound first, then the thesis's 0.25 m, as the pipeline does.
  options.max_correspondence_distance = 1.0;
  IcpResult result = align(scene.source, target, &normals, Eigen::Isometry3d::Identity(), options);
  options.max_correspondence_distance = 0.25;
  result = align(scene.source, target, &normals, result.transform, options);
  EXPECT_GT(result.iterations, 0);  // the kernel variants may still creep at the iteration cap; fine
  EXPECT_LT(translation_error(result.transform, scene.truth), 0.01);
  EXPECT_LT(rotation_error(result.transform, scene.truth), 0.002);
  EXPECT_LT(result.rmse, 0.08);  // 0.1 m sampling: nearest points are up to ~7 cm apart
  EXPECT_GT(result.pairs.size(), scene.source.size() * 9 / 10);
}

INSTANTIATE_TEST_SUITE_P(Variants, IcpRecovers,
                         testing::Values(std::tuple{IcpMetric::kPointToPoint, RotationSolver::kSvd, 0.0},
                                         std::tuple{IcpMetric::kPointToPoint,
                                                    RotationSolver::kPolarDenmanBeavers, 0.0},
                                         std::tuple{IcpMetric::kPointToPoint, RotationSolver::kSvd, 0.1},
                                         std::tuple{IcpMetric::kPointToPlane, RotationSolver::kSvd, 0.0},
                                         std::tuple{IcpMetric::kPointToPlane, RotationSolver::kSvd, 0.1}));

TEST(Icp, ExactCopyIsRecoveredExactly) {
  const PointCloud target = test::room_scene(0.2, 0.0, 3);
  const Eigen::Isometry3d truth = make_transform(0.1, 0.05, 0.0, 0.0, 0.0, 0.05);
  const GrowingKdTree tree(target);
  IcpOptions options;
  options.metric = IcpMetric::kPointToPoint;
  options.kernel_scale = 0.0;
  options.mse_change_threshold = 1e-14;
  options.max_iterations = 200;
  const IcpResult result =
      align(transformed(target, truth.inverse()), tree, nullptr, Eigen::Isometry3d::Identity(), options);
  EXPECT_LT(translation_error(result.transform, truth), 1e-4);
  EXPECT_LT(result.rmse, 1e-3);
}

TEST(Icp, NoTargetWithinTheBoundLeavesTheGuess) {
  const GrowingKdTree target(PointCloud{{100, 0, 0}, {100, 1, 0}, {100, 0, 1}});
  const Eigen::Isometry3d guess = make_transform(1, 2, 3, 0, 0, 0.5);
  const IcpResult result = align(test::room_scene(0.5), target, nullptr, guess, IcpOptions{});
  EXPECT_TRUE(result.transform.isApprox(guess));
  EXPECT_EQ(result.iterations, 0);
  EXPECT_TRUE(result.pairs.empty());
}

TEST(Icp, StopsWhenTheStepsAreSmall) {
  const Scene scene = moved_room(make_transform(0.1, -0.05, 0.02, 0.0, 0.01, 0.04), 0.25);
  const GrowingKdTree tree(scene.target);
  IcpOptions options;
  options.mse_change_threshold = 0.0;  // the MSE never stops it: only the step limits or the cap can
  options.max_iterations = 40;
  const IcpResult capped = align(scene.source, tree, nullptr, Eigen::Isometry3d::Identity(), options);
  EXPECT_FALSE(capped.converged);
  EXPECT_EQ(capped.iterations, 40);

  options.min_step_translation = 1e-4;
  options.min_step_rotation = 1e-4;
  const IcpResult stopped = align(scene.source, tree, nullptr, Eigen::Isometry3d::Identity(), options);
  EXPECT_TRUE(stopped.converged);
  EXPECT_LT(stopped.iterations, 40);
  EXPECT_LT(translation_error(stopped.transform, scene.truth), 0.02);
  EXPECT_LT(rotation_error(stopped.transform, scene.truth), 0.005);
}

TEST(RegisterScan, EachStageThinsTheSourceToItsOwnVoxel) {
  const Scene scene = moved_room(make_transform(0.2, 0.1, 0.0, 0.0, 0.0, 0.05), 0.2);
  RegistrationOptions options;
  options.stages = {{.max_correspondence_distance = 1.0,
                     .source_voxel_size = 0.8,
                     .min_step_translation = 1e-3,
                     .min_step_rotation = 1e-3},
                    {.max_correspondence_distance = 0.25,
                     .source_voxel_size = 0.3,
                     .min_step_translation = 1e-4,
                     .min_step_rotation = 1e-4}};
  const RegistrationResult two =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  std::swap(options.stages.front().source_voxel_size, options.stages.back().source_voxel_size);
  const RegistrationResult swapped =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  // The result reports the last stage's points: fewer with the coarser voxel last.
  EXPECT_LT(swapped.source_points, two.source_points);
  EXPECT_TRUE(two.accepted()) << two.assessment.message;
  EXPECT_LT(translation_error(two.transform, scene.truth), 0.03);

  options.stages.clear();
  EXPECT_THROW(
      static_cast<void>(register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options)),
      std::invalid_argument);
}

TEST(RegisterScan, TheDegeneracyCheckUsesAtMostTheSampleOfPairs) {
  const Scene scene = moved_room(make_transform(0.1, 0.0, 0.0, 0.0, 0.0, 0.02), 0.2);
  RegistrationOptions options;
  options.max_constraint_pairs = 50;
  const RegistrationResult sampled =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  ASSERT_GT(sampled.pairs, 50U);
  EXPECT_LE(sampled.constraint.normals_used, 50U);
  options.max_constraint_pairs = 0;
  const RegistrationResult all =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  EXPECT_GT(all.constraint.normals_used, 50U);
  // A spread sample measures the same geometry: the room constrains every direction either way.
  EXPECT_NEAR(sampled.constraint.weakest, all.constraint.weakest, 0.05);
}

TEST(RegisterScan, ASourceOverThePointBudgetIsSampledDownAndStillRecovered) {
  const Scene scene = moved_room(make_transform(0.2, -0.1, 0.05, 0.01, 0.0, 0.06), 0.1);
  RegistrationOptions options;
  const RegistrationResult all =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  ASSERT_GT(all.source_points, 400U);
  options.max_source_points = 400;
  const RegistrationResult budgeted =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  EXPECT_EQ(budgeted.source_points, 400U);
  EXPECT_TRUE(budgeted.accepted()) << budgeted.assessment.message;
  EXPECT_LT(translation_error(budgeted.transform, scene.truth), 0.03);
  EXPECT_LT(rotation_error(budgeted.transform, scene.truth), 0.005);
  // Spread over the scan, the sample pairs as large a share of its points as the whole source does.
  const double share = static_cast<double>(budgeted.pairs) / static_cast<double>(budgeted.source_points);
  EXPECT_NEAR(share, static_cast<double>(all.pairs) / static_cast<double>(all.source_points), 0.1);
}

// The coarse stage only has to bring the guess within the fine stage's bound: a budget of its own, below
// the fine stage's, recovers the offset as closely (the localizer's 300 and 1,000).
TEST(RegisterScan, AStageWithABudgetOfItsOwnRegistersAsClosely) {
  const Scene scene = moved_room(make_transform(0.5, 0.3, 0.1, 0.02, 0.03, 0.14), 0.1);
  RegistrationOptions options;
  options.max_source_points = 400;
  options.stages.front().max_source_points = 100;
  const RegistrationResult result =
      register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options);
  EXPECT_EQ(result.source_points, 400U);  // the last stage's
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  EXPECT_LT(translation_error(result.transform, scene.truth), 0.03);
  EXPECT_LT(rotation_error(result.transform, scene.truth), 0.005);
  // A stage's own budget is the one it registers with.
  options.stages.pop_back();
  EXPECT_EQ(register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity(), options).source_points,
            100U);
}

TEST(RegisterScan, RecoversALargerOffsetCoarseToFine) {
  // 0.6 m and 8 degrees off: farther than the final 0.25 m bound reaches on its own.
  const Scene scene = moved_room(make_transform(0.5, 0.3, 0.1, 0.02, 0.03, 0.14));
  const RegistrationResult result = register_scan(scene.source, scene.target, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  EXPECT_LT(translation_error(result.transform, scene.truth), 0.03);
  EXPECT_LT(rotation_error(result.transform, scene.truth), 0.005);
  EXPECT_GT(result.iterations, 0);
  EXPECT_GT(result.pairs, 100U);
}

}  // namespace
}  // namespace strata

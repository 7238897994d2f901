#include "core/registration/fault_check.hpp"

#include <gtest/gtest.h>

#include "core/registration/register_scan.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

using test::make_transform;

RegistrationEvidence good_evidence() {
  RegistrationEvidence evidence;
  evidence.pairs = 1000;
  evidence.source_points = 1200;
  evidence.rmse = 0.05;
  evidence.constraint.weakest = 0.2;
  return evidence;
}

TEST(FaultCheck, AcceptsGoodEvidence) {
  const Assessment a = assess(good_evidence(), FaultLimits{});
  EXPECT_EQ(a.verdict, Verdict::kAccepted);
  EXPECT_EQ(a.reason, RejectReason::kNone);
}

TEST(FaultCheck, RejectsEachBadCaseWithItsReason) {
  const FaultLimits limits;
  RegistrationEvidence few = good_evidence();
  few.pairs = 50;
  EXPECT_EQ(assess(few, limits).reason, RejectReason::kTooFewPairs);
  RegistrationEvidence small_share = good_evidence();
  small_share.source_points = 10000;  // 1000 pairs = 10 %
  EXPECT_EQ(assess(small_share, limits).reason, RejectReason::kTooFewPairs);
  RegistrationEvidence residual = good_evidence();
  residual.rmse = 0.3;
  EXPECT_EQ(assess(residual, limits).reason, RejectReason::kHighResidual);
  RegistrationEvidence jump = good_evidence();
  jump.result = make_transform(2.0, 0, 0, 0, 0, 0);
  EXPECT_EQ(assess(jump, limits).reason, RejectReason::kJumpFromGuess);
  RegistrationEvidence turn = good_evidence();
  turn.result = make_transform(0, 0, 0, 0, 0, 0.5);
  const Assessment turned = assess(turn, limits);
  EXPECT_EQ(turned.reason, RejectReason::kJumpFromGuess);
  EXPECT_NE(turned.message.find("deg"), std::string::npos);
  RegistrationEvidence corridor = good_evidence();
  corridor.constraint.weakest = 0.001;
  EXPECT_EQ(assess(corridor, limits).reason, RejectReason::kDegenerateGeometry);
  EXPECT_EQ(assess(corridor, limits).verdict, Verdict::kRejected);
}

TEST(FaultCheck, StraightCorridorIsFlaggedDegenerateAndTheGuessKept) {
  const PointCloud corridor = test::corridor_scene();
  const Eigen::Isometry3d truth = make_transform(0.3, 0.05, 0.0, 0.0, 0.0, 0.02);
  const Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  const RegistrationResult result = register_scan(transformed(corridor, truth.inverse()), corridor, guess);
  EXPECT_EQ(result.assessment.reason, RejectReason::kDegenerateGeometry) << result.assessment.message;
  EXPECT_TRUE(result.transform.isApprox(guess));  // on reject the caller keeps the guess
  EXPECT_LT(result.constraint.weakest, 0.01);
  EXPECT_GT(std::abs(result.constraint.weakest_direction.x()), 0.95);  // the corridor's axis
}

TEST(FaultCheck, RoomIsWellConstrained) {
  const PointCloud room = test::room_scene();
  const RegistrationResult result = register_scan(room, room, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  EXPECT_GT(result.constraint.weakest, 0.05);
}

TEST(FaultCheck, TooLittleOverlapIsRejected) {
  // The source overlaps the target in one small corner only.
  const PointCloud room = test::room_scene();
  PointCloud corner;
  for (const Eigen::Vector3d& p : room) {
    if (p.x() > 4.0 && p.y() > 3.0)
      corner.push_back(p);
  }
  PointCloud elsewhere = transformed(test::room_scene(), make_transform(40, 0, 0, 0, 0, 0));
  elsewhere.insert(elsewhere.end(), corner.begin(), corner.end());
  const RegistrationResult result = register_scan(elsewhere, room, Eigen::Isometry3d::Identity());
  EXPECT_EQ(result.assessment.reason, RejectReason::kTooFewPairs) << result.assessment.message;
}

TEST(FaultCheck, FarJumpIsRejected) {
  // ICP finds the true 0.6 m offset, but odometry is trusted to 0.2 m here: a result that far from the
  // guess is more likely a slide into the wrong surfaces than a true correction, so it is refused.
  const PointCloud room = test::room_scene();
  RegistrationOptions options;
  options.limits.max_translation_jump = 0.2;
  const Eigen::Isometry3d truth = make_transform(0.6, 0, 0, 0, 0, 0);
  const RegistrationResult result =
      register_scan(transformed(room, truth.inverse()), room, Eigen::Isometry3d::Identity(), options);
  EXPECT_EQ(result.assessment.reason, RejectReason::kJumpFromGuess) << result.assessment.message;
  EXPECT_TRUE(result.transform.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_LT(test::translation_error(result.refined, truth), 0.05);  // ICP itself was right
}

}  // namespace
}  // namespace strata

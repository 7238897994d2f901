#include "core/registration/register_scan.hpp"

#include <gtest/gtest.h>

#include "core/localization/scan_to_map_localizer.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

PointCloud shifted(PointCloud points, const Eigen::Vector3d& by) {
  for (Eigen::Vector3d& p : points)
    p += by;
  return points;
}

RegistrationResult fresh(const PointCloud& target, const PointCloud& source, const Eigen::Isometry3d& guess) {
  ScanRegistration registration(LocalizerOptions::default_registration());
  registration.set_thinned_target(target);
  return registration.register_scan(source, guess);
}

void expect_same(const RegistrationResult& a, const RegistrationResult& b) {
  EXPECT_EQ(a.pairs, b.pairs);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_LT((a.refined.matrix() - b.refined.matrix()).norm(), 1e-9);
}

// A target that grows at its end is indexed piece by piece (GrowingKdTree), and every registration against
// it is the one a target built afresh from the same points gives; a new layout is indexed afresh.
TEST(ScanRegistration, FollowingAGrowingTargetRegistersAsAFreshTargetDoes) {
  const PointCloud room = test::room_scene(0.1, 0.0, 3);
  const PointCloud source = test::room_scene(0.1, 0.005, 4);
  const Eigen::Isometry3d guess = test::make_transform(0.15, -0.1, 0.02, 0.0, 0.0, 0.05);
  ScanRegistration following(LocalizerOptions::default_registration());
  PointCloud target(room.begin(), room.begin() + static_cast<std::ptrdiff_t>(room.size() / 2));
  std::size_t grown = target.size();
  for (const std::size_t piece : {room.size() / 20, room.size() / 10, room.size() / 4, room.size() / 10}) {
    const std::size_t next = std::min(room.size(), grown + piece);
    target.insert(target.end(), room.begin() + static_cast<std::ptrdiff_t>(grown),
                  room.begin() + static_cast<std::ptrdiff_t>(next));
    grown = next;
    following.follow_target(target, 1, {}, {});  // normals afresh too: the index alone compared
    expect_same(following.register_scan(source, guess), fresh(target, source, guess));
  }
  // The same size, other points (a local map moved by a loop closure): a new layout, indexed afresh.
  const PointCloud moved = shifted(target, {0.3, 0.0, 0.0});
  following.follow_target(moved, 2, {}, {});
  expect_same(following.register_scan(source, guess), fresh(moved, source, guess));
}

}  // namespace
}  // namespace strata

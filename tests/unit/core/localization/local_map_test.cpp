#include "core/localization/local_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <utility>

#include "core/points/voxel_downsample.hpp"
#include "core/points/voxel_key.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

std::set<VoxelKey> voxels_of(const PointCloud& points, double voxel) {
  std::set<VoxelKey> keys;
  for (const Eigen::Vector3d& p : points)
    keys.insert(voxel_key(voxel_cell(p, 1.0 / voxel)));
  return keys;
}

PointCloud shifted(PointCloud points, double dx) {
  for (Eigen::Vector3d& p : points)
    p.x() += dx;
  return points;
}

// The map holds what thinning the concatenation of the last N scans holds (the same voxels, one point each),
// and voxels no recent scan reached only while they are under a quarter of it: they are dropped together.
TEST(LocalMap, HoldsTheVoxelsOfTheLastScans) {
  const double voxel = 0.1;
  const std::size_t keep = 3;
  LocalMap map(voxel, keep);
  std::vector<PointCloud> scans;
  std::uint64_t layout = map.layout();
  std::size_t compactions = 0;
  for (int i = 0; i < 12; ++i) {
    scans.push_back(shifted(test::room_scene(0.05, 0.0, static_cast<unsigned>(i)), 0.2 * i));
    const std::size_t before = map.size();
    const PointCloud old(map.points());
    map.add(scans.back(), Eigen::Vector3d::Zero());
    PointCloud recent;
    for (std::size_t k = scans.size() > keep ? scans.size() - keep : 0; k < scans.size(); ++k)
      recent.insert(recent.end(), scans[k].begin(), scans[k].end());
    const std::set<VoxelKey> held = voxels_of(map.points(), voxel);
    const std::set<VoxelKey> live = voxels_of(voxel_downsample(recent, voxel), voxel);
    EXPECT_TRUE(std::includes(held.begin(), held.end(), live.begin(), live.end())) << "scan " << i;
    EXPECT_LT(4 * (held.size() - live.size()), map.size()) << "scan " << i;
    EXPECT_EQ(map.size(), held.size()) << "one point per voxel";
    if (map.layout() == layout) {  // grown at the end only: the points before kept their places
      ASSERT_GE(map.size(), before);
      EXPECT_TRUE(std::equal(old.begin(), old.end(), map.points().begin())) << "scan " << i;
    } else {
      ++compactions;
      layout = map.layout();
    }
  }
  EXPECT_GT(compactions, 0U);
  EXPECT_LT(compactions, 11U);
}

// A voxel a newer scan reached again stays, with its first point; one no recent scan reached expires.
TEST(LocalMap, RevisitedVoxelsStayAndKeepTheirFirstPoint) {
  LocalMap map(1.0, 2);
  map.add({{0.1, 0.1, 0.1}, {5.1, 0.1, 0.1}}, Eigen::Vector3d::Zero());
  map.add({{0.9, 0.9, 0.9}}, Eigen::Vector3d::Zero());
  map.add({{0.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());  // (5, 0, 0) was last reached two scans ago: expired
  ASSERT_EQ(map.size(), 1U);
  EXPECT_EQ(map.points().front(), Eigen::Vector3d(0.1, 0.1, 0.1));
  map.add({{7.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  map.add({{7.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());  // (0, 0, 0) last reached three scans ago
  ASSERT_EQ(map.size(), 1U);
  EXPECT_EQ(map.points().front(), Eigen::Vector3d(7.5, 0.5, 0.5));
}

// Normals estimated against the map travel with their points through growth and expiry; ones that do not
// match the map are dropped.
TEST(LocalMap, CarriesNormalsWithTheirPoints) {
  LocalMap map(1.0, 2);
  map.add({{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  LazyNormals::Estimates estimates;
  estimates.normals = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  estimates.states = {LazyNormals::State::kValid, LazyNormals::State::kInvalid};
  map.keep_normals(estimates);
  map.add({{1.5, 0.6, 0.5}, {2.5, 0.5, 0.5}},
          Eigen::Vector3d::Zero());                     // refreshes the second voxel, adds a third
  map.add({{2.5, 0.6, 0.5}}, Eigen::Vector3d::Zero());  // the first voxel expires
  LazyNormals::Estimates carried = map.take_normals();
  ASSERT_EQ(map.size(), 2U);
  ASSERT_EQ(carried.states.size(), 2U);
  EXPECT_EQ(carried.states[0], LazyNormals::State::kInvalid);                    // (1.5, 0.5, 0.5)'s
  EXPECT_EQ(carried.states[1], LazyNormals::State::kUnknown);                    // new since
  map.keep_normals({{Eigen::Vector3d::UnitZ()}, {LazyNormals::State::kValid}});  // one for two points
  EXPECT_TRUE(map.take_normals().states.empty());
}

// Each point keeps where the sensor was that first saw it (the thin-wall side test needs it): through a
// revisit, expiry and a correction of the map frame, which turns the viewpoints with the points.
TEST(LocalMap, CarriesViewpointsWithTheirPoints) {
  LocalMap map(1.0, 2);
  const Eigen::Vector3d first_sensor(0.0, -3.0, 0.5);
  const Eigen::Vector3d second_sensor(0.0, 3.0, 0.5);
  map.add({{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}}, first_sensor);
  map.add({{1.5, 0.6, 0.5}, {2.5, 0.5, 0.5}}, second_sensor);  // revisits the second voxel, adds a third
  map.add({{2.5, 0.6, 0.5}}, second_sensor);                   // the first voxel expires
  ASSERT_EQ(map.size(), 2U);
  ASSERT_EQ(map.viewpoints().size(), 2U);
  EXPECT_EQ(map.points()[0], Eigen::Vector3d(1.5, 0.5, 0.5));
  EXPECT_EQ(map.viewpoints()[0], first_sensor) << "a revisit keeps the first sensor, as it keeps the point";
  EXPECT_EQ(map.viewpoints()[1], second_sensor);

  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  correction.rotate(Eigen::AngleAxisd(std::numbers::pi / 2.0, Eigen::Vector3d::UnitZ()));
  correction.pretranslate(Eigen::Vector3d(10.0, 0.0, 0.0));
  map.transform(correction);
  ASSERT_EQ(map.size(), 2U);
  ASSERT_EQ(map.viewpoints().size(), 2U);
  for (std::size_t i = 0; i < map.size(); ++i) {
    const Eigen::Vector3d before = correction.inverse() * map.points()[i];
    const Eigen::Vector3d seen_from = before.x() < 2.0 ? first_sensor : second_sensor;
    EXPECT_TRUE(map.viewpoints()[i].isApprox(correction * seen_from)) << "point " << i;
  }
}

// Two points a correction moves into one voxel keep the older point and the older point's viewpoint.
TEST(LocalMap, MergedVoxelsKeepTheOlderViewpoint) {
  LocalMap map(1.0, 2);
  const Eigen::Vector3d first_sensor(-2.0, 0.0, 0.5);
  const Eigen::Vector3d second_sensor(4.0, 0.0, 0.5);
  map.add({{0.9, 0.5, 0.5}}, first_sensor);
  map.add({{1.1, 0.5, 0.5}}, second_sensor);
  map.transform(Eigen::Isometry3d(Eigen::Translation3d(0.15, 0.0, 0.0)));
  ASSERT_EQ(map.size(), 1U);
  ASSERT_EQ(map.viewpoints().size(), 1U);
  EXPECT_TRUE(map.points()[0].isApprox(Eigen::Vector3d(1.05, 0.5, 0.5)));
  EXPECT_TRUE(map.viewpoints()[0].isApprox(first_sensor + Eigen::Vector3d(0.15, 0.0, 0.0)));
}

TEST(LocalMap, KeepsWhatTheSensorPassedInTheLastMetresWhateverTheScanRate) {
  // Two scans kept by count, 1 m by distance; the sensor moves 0.4 m a scan.
  LocalMap map(1.0, 2, 1.0);
  map.add({{0.5, 0.5, 0.5}}, {0.0, 0, 0});
  map.add({{1.5, 0.5, 0.5}}, {0.4, 0, 0});
  map.add({{2.5, 0.5, 0.5}}, {0.8, 0, 0});
  EXPECT_EQ(map.size(), 3U);  // the first is three scans old but only 0.8 m behind: kept
  map.add({{3.5, 0.5, 0.5}}, {1.2, 0, 0});
  EXPECT_EQ(map.size(), 3U);  // now 1.2 m behind: gone
  EXPECT_EQ(map.points().front().x(), 1.5);
  // Standing still, nothing it saw expires, however many scans come.
  for (int i = 0; i < 10; ++i)
    map.add({{3.5, 0.5, 0.5}}, {1.2, 0, 0});
  EXPECT_EQ(map.size(), 3U);
}

/// The local map's rule as a pass over every point at every scan (LocalMap counts its expired voxels per
/// scan instead): what the map must hold, point for point, after every scan and correction.
class PassOverEveryPoint {
 public:
  PassOverEveryPoint(double voxel, std::size_t scans, double metres)
      : inverse_(1.0 / voxel), scans_(scans), metres_(metres) {}

  void add(const PointCloud& points, const Eigen::Vector3d& sensor) {
    ++scan_;
    if (last_sensor_)
      travelled_ += (sensor - *last_sensor_).norm();
    last_sensor_ = sensor;
    for (const Eigen::Vector3d& p : points) {
      const auto [at, added] = voxels_.try_emplace(voxel_key(voxel_cell(p, inverse_)), points_.size());
      if (added) {
        points_.push_back(p);
        viewpoints_.push_back(sensor);
        seen_.push_back(scan_);
        seen_at_.push_back(travelled_);
      } else {
        seen_[at->second] = scan_;
        seen_at_[at->second] = travelled_;
      }
    }
    if (scan_ <= scans_)
      return;
    const std::uint32_t oldest_kept = scan_ - static_cast<std::uint32_t>(scans_) + 1;
    const auto live = [&](std::size_t i) {
      return seen_[i] >= oldest_kept || (metres_ > 0.0 && travelled_ - seen_at_[i] <= metres_);
    };
    std::size_t expired = 0;
    for (std::size_t i = 0; i < points_.size(); ++i)
      expired += live(i) ? 0 : 1;
    if (expired == 0 || 4 * expired < points_.size())
      return;
    keep_where(live, Eigen::Isometry3d::Identity());
  }

  void transform(const Eigen::Isometry3d& transform) {
    keep_where([](std::size_t) { return true; }, transform);
  }

  [[nodiscard]] const PointCloud& points() const { return points_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& viewpoints() const { return viewpoints_; }

 private:
  /// The points `keep` keeps, moved by `transform` and hashed again: of two in one voxel, the older stays
  /// with the later one's last sight.
  template <class Keep>
  void keep_where(Keep keep, const Eigen::Isometry3d& transform) {
    PointCloud points;
    std::vector<Eigen::Vector3d> viewpoints;
    std::vector<std::uint32_t> seen;
    std::vector<double> seen_at;
    voxels_.clear();
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!keep(i))
        continue;
      const Eigen::Vector3d p = transform * points_[i];
      const auto [at, added] = voxels_.try_emplace(voxel_key(voxel_cell(p, inverse_)), points.size());
      if (added) {
        points.push_back(p);
        viewpoints.push_back(transform * viewpoints_[i]);
        seen.push_back(seen_[i]);
        seen_at.push_back(seen_at_[i]);
      } else {
        seen[at->second] = std::max(seen[at->second], seen_[i]);
        seen_at[at->second] = std::max(seen_at[at->second], seen_at_[i]);
      }
    }
    points_ = std::move(points);
    viewpoints_ = std::move(viewpoints);
    seen_ = std::move(seen);
    seen_at_ = std::move(seen_at);
  }

  double inverse_;
  std::size_t scans_;
  double metres_;
  std::uint32_t scan_ = 0;
  double travelled_ = 0.0;
  std::optional<Eigen::Vector3d> last_sensor_;
  PointCloud points_;
  std::vector<Eigen::Vector3d> viewpoints_;
  std::vector<std::uint32_t> seen_;
  std::vector<double> seen_at_;
  std::map<VoxelKey, std::size_t> voxels_;
};

// Expiry counted per scan keeps, drops and merges exactly the points a pass over the whole map at every
// scan would: a sensor that wanders, stops, and turns back over what it saw, with corrections between.
TEST(LocalMap, ExpiresExactlyAsAPassOverEveryPointWould) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const double metres : {0.0, 2.0}) {
    LocalMap map(0.5, 3, metres);
    PassOverEveryPoint reference(0.5, 3, metres);
    Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
    std::size_t compactions = 0;
    std::uint64_t layout = map.layout();
    for (int step = 0; step < 400; ++step) {
      if (step % 5 != 4)  // every fifth scan from where the last one was taken
        sensor += Eigen::Vector3d(0.4 * unit(random), 0.4 * unit(random), 0.0);
      PointCloud scan;
      for (int k = 0; k < 40; ++k)
        scan.push_back(sensor + Eigen::Vector3d(3.0 * unit(random), 3.0 * unit(random), unit(random)));
      if (step % 37 == 36) {
        const Eigen::Isometry3d correction(Eigen::Translation3d(0.3 * unit(random), 0.3 * unit(random), 0.0) *
                                           Eigen::AngleAxisd(0.05 * unit(random), Eigen::Vector3d::UnitZ()));
        map.transform(correction);
        reference.transform(correction);
        sensor = correction * sensor;
      }
      map.add(scan, sensor);
      reference.add(scan, sensor);
      ASSERT_EQ(map.points(), reference.points()) << "metres " << metres << ", scan " << step;
      ASSERT_EQ(map.viewpoints(), reference.viewpoints()) << "metres " << metres << ", scan " << step;
      compactions += std::exchange(layout, map.layout()) != map.layout() ? 1 : 0;
    }
    EXPECT_GT(compactions, 20U) << "metres " << metres;
  }
}

// A scan given in its own frame with its pose lands as the same scan moved into the map frame first.
TEST(LocalMap, AScanWithItsPoseIsTheScanMovedIntoTheMapFrame) {
  const Eigen::Isometry3d map_from_scan(Eigen::Translation3d(2.0, -1.0, 0.3) *
                                        Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const PointCloud scan = test::room_scene(0.05, 0.0, 3);
  const Eigen::Vector3d sensor(0.1, 0.0, 0.5);
  LocalMap with_pose(0.1, 3);
  LocalMap moved(0.1, 3);
  with_pose.add(scan, map_from_scan, sensor);
  moved.add(transformed(scan, map_from_scan), map_from_scan * sensor);
  EXPECT_EQ(with_pose.points(), moved.points());
  EXPECT_EQ(with_pose.viewpoints(), moved.viewpoints());
}

// An earlier pass's points join as if the latest scan had reached them: new voxels take them (moved into
// the map frame, seen from where that pass's sensor was), a voxel this pass holds keeps its point, and they
// expire with the latest scan. Before any scan there is nothing to join.
TEST(LocalMap, AnEarlierPassJoinsAsTheLatestScanWithoutMovingTheSensor) {
  LocalMap map(1.0, 2);
  const Eigen::Isometry3d earlier_pose(Eigen::Translation3d(10.0, 0.0, 0.0));
  const Eigen::Vector3d earlier_sensor(0.0, 0.0, 0.5);
  map.join({{0.5, 0.5, 0.5}}, earlier_pose, earlier_sensor);
  EXPECT_TRUE(map.empty()) << "no scan yet";

  map.add({{10.2, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  const std::uint64_t layout = map.layout();
  map.join({{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}}, earlier_pose, earlier_sensor);  // (10.5, ..) is held
  ASSERT_EQ(map.size(), 2U);
  EXPECT_EQ(map.layout(), layout) << "grown at the end";
  EXPECT_EQ(map.points()[0], Eigen::Vector3d(10.2, 0.5, 0.5)) << "this pass's point stays";
  EXPECT_EQ(map.points()[1], Eigen::Vector3d(11.5, 0.5, 0.5));
  EXPECT_EQ(map.viewpoints()[1], earlier_pose * earlier_sensor);

  // Two scans kept: the joined voxel lives as long as the scan it joined.
  map.add({{20.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  EXPECT_EQ(map.size(), 3U);
  map.add({{20.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  map.add({{20.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  ASSERT_EQ(map.size(), 1U) << "(10, 0, 0) and (11, 0, 0) expired together";
  EXPECT_EQ(map.points()[0], Eigen::Vector3d(20.5, 0.5, 0.5));

  // Kept by metres: the earlier sensor 100 m away is not a way the sensor drove.
  LocalMap by_metres(1.0, 1, 5.0);
  by_metres.add({{0.5, 0.5, 0.5}}, Eigen::Vector3d::Zero());
  by_metres.join({{0.5, 5.5, 0.5}}, Eigen::Isometry3d::Identity(), Eigen::Vector3d(100.0, 0.0, 0.0));
  by_metres.add({{1.5, 0.5, 0.5}}, Eigen::Vector3d(1.0, 0.0, 0.0));
  by_metres.add({{1.5, 0.5, 0.5}}, Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_EQ(by_metres.size(), 3U) << "1 m driven of the 5 kept";
}

}  // namespace
}  // namespace strata

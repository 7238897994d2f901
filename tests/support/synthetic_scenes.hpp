#pragma once

#include <Eigen/Geometry>
#include <random>

#include "core/points/point_cloud.hpp"

namespace strata::test {

/// Points on an axis-aligned rectangle: the face of `box_min`..`box_max` with `fixed_axis` held at
/// `fixed_value`, one per `step` x `step` on average, at random places (a regular grid would give ICP
/// false minima one grid step apart, which real scans do not have), with Gaussian noise `sigma`.
inline void add_face(PointCloud& cloud, int fixed_axis, double fixed_value, const Eigen::Vector3d& box_min,
                     const Eigen::Vector3d& box_max, double step, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  const int a = (fixed_axis + 1) % 3;
  const int b = (fixed_axis + 2) % 3;
  std::uniform_real_distribution<double> along_a(box_min[a], box_max[a]);
  std::uniform_real_distribution<double> along_b(box_min[b], box_max[b]);
  const auto count = static_cast<int>((box_max[a] - box_min[a]) * (box_max[b] - box_min[b]) / (step * step));
  for (int i = 0; i < count; ++i) {
    Eigen::Vector3d p;
    p[fixed_axis] = fixed_value;
    p[a] = along_a(rng);
    p[b] = along_b(rng);
    cloud.push_back(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
}

/// A 10 m x 8 m room, 3 m high, with a crate and a pillar: every direction constrained.
inline PointCloud room_scene(double step = 0.1, double sigma = 0.005, unsigned seed = 1) {
  std::mt19937 rng(seed);
  PointCloud cloud;
  const Eigen::Vector3d lo(-5, -4, 0), hi(5, 4, 3);
  add_face(cloud, 2, 0.0, lo, hi, step, sigma, rng);   // floor
  add_face(cloud, 0, -5.0, lo, hi, step, sigma, rng);  // walls
  add_face(cloud, 0, 5.0, lo, hi, step, sigma, rng);
  add_face(cloud, 1, -4.0, lo, hi, step, sigma, rng);
  add_face(cloud, 1, 4.0, lo, hi, step, sigma, rng);
  const Eigen::Vector3d crate_lo(1, 1, 0), crate_hi(2.5, 2, 1);
  add_face(cloud, 0, 1.0, crate_lo, crate_hi, step, sigma, rng);
  add_face(cloud, 1, 1.0, crate_lo, crate_hi, step, sigma, rng);
  add_face(cloud, 2, 1.0, crate_lo, crate_hi, step, sigma, rng);
  const Eigen::Vector3d pillar_lo(-2, -1.5, 0), pillar_hi(-1.6, -1.1, 3);
  add_face(cloud, 0, -2.0, pillar_lo, pillar_hi, step, sigma, rng);
  add_face(cloud, 1, -1.5, pillar_lo, pillar_hi, step, sigma, rng);
  return cloud;
}

/// A straight corridor along x: floor, ceiling and two walls, nothing across it. Translation along x is
/// unobservable.
inline PointCloud corridor_scene(double step = 0.1, unsigned seed = 2) {
  std::mt19937 rng(seed);
  PointCloud cloud;
  const Eigen::Vector3d lo(-15, -1, 0), hi(15, 1, 2.5);
  add_face(cloud, 2, 0.0, lo, hi, step, 0.005, rng);
  add_face(cloud, 2, 2.5, lo, hi, step, 0.005, rng);
  add_face(cloud, 1, -1.0, lo, hi, step, 0.005, rng);
  add_face(cloud, 1, 1.0, lo, hi, step, 0.005, rng);
  return cloud;
}

inline Eigen::Isometry3d make_transform(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x, y, z);
  t.linear() =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return t;
}

inline double translation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}
inline double rotation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd((a.inverse() * b).rotation()).angle();
}

}  // namespace strata::test

#include "drivers/replay/reference_odometry.hpp"

#include <cmath>
#include <random>

namespace strata::replay {

std::vector<Pose3> odometry_from_reference(const std::vector<Pose3>& reference, const OdometryNoise& noise,
                                           std::uint64_t seed) {
  std::vector<Pose3> odometry;
  if (reference.empty())
    return odometry;
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  const auto planar = [](const Pose3& pose) { return Pose2{pose.position.x(), pose.position.y(), pose.yaw}; };
  Pose2 current = planar(reference.front());
  odometry.push_back(Pose3::from_pose2(current));
  for (std::size_t i = 1; i < reference.size(); ++i) {
    Pose2 step = planar(reference[i]).relative_to(planar(reference[i - 1]));
    const double distance = std::hypot(step.x, step.y);
    step.x += gaussian(random) * noise.translation * distance;
    step.y += gaussian(random) * noise.translation * distance;
    step.theta += gaussian(random) * noise.rotation * distance;
    current = current.compose(step);
    odometry.push_back(Pose3::from_pose2(current));
  }
  return odometry;
}

}  // namespace strata::replay

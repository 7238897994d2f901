#include "core/registration/surface_sides.hpp"

#include <algorithm>
#include <cmath>

namespace strata {
namespace {

/// The 16-bit bin of `value`, wrapped: surfaces 65,536 bins apart share a key, which only merges their
/// free offsets. Wrapped in floating point, so that no value (however far, or not finite) is cast out of
/// range.
std::uint64_t bin(double value, double size) {
  const double cell = std::floor(value / size);
  if (!std::isfinite(cell))
    return 0U;
  constexpr double kBins = 65536.0;
  const double wrapped = cell - kBins * std::floor(cell / kBins);  // in [0, kBins]: rounding may reach it
  return static_cast<std::uint64_t>(wrapped) & 0xffffU;
}

}  // namespace

void split_across(const Eigen::Isometry3d& source_to_target, const PointCloud& target, LazyNormals& normals,
                  const SurfaceSides& sides, const SurfaceSideOptions& options,
                  std::vector<Correspondence>& pairs, std::vector<AcrossPair>& across) {
  across.clear();
  if (sides.target_viewpoints == nullptr || sides.target_viewpoints->size() != target.size())
    return;
  const Eigen::Vector3d sensor = source_to_target * sides.source_viewpoint;
  const std::vector<Eigen::Vector3d>& viewpoints = *sides.target_viewpoints;
  const auto sure = [&](double distance, double range) {
    return std::abs(distance) > options.margin + options.normal_error * range;
  };
  std::erase_if(pairs, [&](const Correspondence& pair) {
    const Eigen::Vector3d* n = normals.at(pair.target);
    if (n == nullptr)
      return false;
    const Eigen::Vector3d& q = target[pair.target];
    const Eigen::Vector3d to_sensor = sensor - q;
    const Eigen::Vector3d to_viewpoint = viewpoints[pair.target] - q;
    const double sensor_side = n->dot(to_sensor);
    const double viewpoint_side = n->dot(to_viewpoint);
    if (sensor_side * viewpoint_side >= 0.0 || !sure(sensor_side, to_sensor.norm()) ||
        !sure(viewpoint_side, to_viewpoint.norm()))
      return false;
    const Eigen::Vector3d facing = sensor_side > 0.0 ? *n : Eigen::Vector3d(-*n);
    const std::uint64_t surface = bin(facing.x(), 0.25) | bin(facing.y(), 0.25) << 16U |
                                  bin(facing.z(), 0.25) << 32U | bin(facing.dot(q), 1.0) << 48U;
    across.push_back({pair, facing, surface});
    return true;
  });
}

}  // namespace strata

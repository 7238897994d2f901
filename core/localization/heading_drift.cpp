#include "core/localization/heading_drift.hpp"

#include <cmath>

#include "core/geometry/angles.hpp"

namespace strata {

std::optional<double> fit_heading_drift(std::span<const HeadingSample> samples,
                                        const HeadingDriftOptions& options) {
  if (!options.enabled || samples.size() < 3)
    return std::nullopt;
  const double last = samples.back().seconds;
  std::size_t first = 0;
  while (first + 1 < samples.size() && last - samples[first].seconds > options.window)
    ++first;
  if (last - samples[first].seconds < options.min_window)
    return std::nullopt;
  // Heading differences unwrapped along the way (a step between keyframes is far below half a turn).
  double sum_s = 0.0, sum_d = 0.0, sum_ss = 0.0, sum_sd = 0.0;
  double previous = 0.0;
  double unwrapped = 0.0;
  for (std::size_t i = first; i < samples.size(); ++i) {
    const double difference = wrap_angle(samples[i].estimated_heading - samples[i].odometry_heading);
    unwrapped = i == first ? difference : unwrapped + wrap_angle(difference - previous);
    previous = difference;
    const double s = samples[i].seconds - samples[first].seconds;
    sum_s += s;
    sum_d += unwrapped;
    sum_ss += s * s;
    sum_sd += s * unwrapped;
  }
  const double n = static_cast<double>(samples.size() - first);
  const double spread = sum_ss - sum_s * sum_s / n;
  if (!(spread > 0.0))
    return std::nullopt;
  const double rate = (sum_sd - sum_s * sum_d / n) / spread;
  if (!std::isfinite(rate) || std::abs(rate) > options.max_rate)
    return std::nullopt;
  return rate;
}

}  // namespace strata

#include "core/localization/heading_drift.hpp"

#include <cmath>
#include <limits>

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

void StandingGyroDrift::add(const StandingGyro& reading) {
  if (!reading.usable())
    return;
  stands_.push_back(reading);
  seconds_ += reading.seconds;
  while (stands_.size() > 1 && seconds_ - stands_.front().seconds >= options_.standing_window) {
    seconds_ -= stands_.front().seconds;
    stands_.pop_front();
  }
  // Summed afresh, once per stand (a few hundred in the window), rather than kept as running sums that
  // would carry the rounding of every stand that left.
  weights_ = 0.0;
  weighted_rates_ = 0.0;
  for (const StandingGyro& stand : stands_) {
    const double weight = 1.0 / (stand.sigma * stand.sigma);
    weights_ += weight;
    weighted_rates_ += weight * stand.rate;
  }
}

std::optional<double> StandingGyroDrift::drift() const {
  if (!options_.enabled || !(sigma() <= options_.standing_max_sigma))
    return std::nullopt;
  return -weighted_rates_ / weights_;
}

double StandingGyroDrift::sigma() const {
  return weights_ > 0.0 ? 1.0 / std::sqrt(weights_) : std::numeric_limits<double>::infinity();
}

}  // namespace strata

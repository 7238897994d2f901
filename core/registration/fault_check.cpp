#include "core/registration/fault_check.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "core/geometry/angles.hpp"

namespace strata {
namespace {

[[gnu::format(printf, 1, 2)]] std::string format(const char* pattern, ...) {
  char buffer[256];
  va_list args;
  va_start(args, pattern);
  std::vsnprintf(buffer, sizeof buffer, pattern, args);
  va_end(args);
  return buffer;
}

Assessment reject(RejectReason reason, std::string message) {
  return {Verdict::kRejected, reason, std::move(message)};
}

}  // namespace

std::string_view to_string(Verdict verdict) {
  return verdict == Verdict::kAccepted ? "accepted" : "rejected";
}

std::string_view to_string(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNone:
      return "none";
    case RejectReason::kTooFewPairs:
      return "too_few_pairs";
    case RejectReason::kHighResidual:
      return "high_residual";
    case RejectReason::kJumpFromGuess:
      return "jump_from_guess";
    case RejectReason::kDegenerateGeometry:
      return "degenerate_geometry";
  }
  return "unknown";
}

Assessment assess(const RegistrationEvidence& evidence, const FaultLimits& limits) {
  const double fraction = evidence.source_points == 0 ? 0.0
                                                      : static_cast<double>(evidence.pairs) /
                                                            static_cast<double>(evidence.source_points);
  if (evidence.pairs < limits.min_pairs || fraction < limits.min_pair_fraction) {
    return reject(
        RejectReason::kTooFewPairs,
        format("%zu pairs (%.0f %% of %zu source points); need %zu and %.0f %%", evidence.pairs,
               100.0 * fraction, evidence.source_points, limits.min_pairs, 100.0 * limits.min_pair_fraction));
  }
  if (!(evidence.rmse <= limits.max_rmse)) {
    return reject(RejectReason::kHighResidual,
                  format("RMSE %.3f m above the limit %.3f m", evidence.rmse, limits.max_rmse));
  }
  const Eigen::Isometry3d jump = evidence.guess.inverse() * evidence.result;
  const double translation = jump.translation().norm();
  const double rotation = Eigen::AngleAxisd(jump.rotation()).angle();
  if (translation > limits.max_translation_jump || rotation > limits.max_rotation_jump) {
    return reject(
        RejectReason::kJumpFromGuess,
        format("result is %.2f m and %.1f deg from the guess; limits %.2f m and %.1f deg", translation,
               rotation * 180.0 / kPi, limits.max_translation_jump, limits.max_rotation_jump * 180.0 / kPi));
  }
  if (evidence.constraint.weakest < limits.min_translation_constraint) {
    const Eigen::Vector3d& d = evidence.constraint.weakest_direction;
    return reject(
        RejectReason::kDegenerateGeometry,
        format("translation along (%.2f, %.2f, %.2f) is unconstrained: normal-matrix eigenvalue "
               "%.4f below %.4f (a corridor or open plane)",
               d.x(), d.y(), d.z(), evidence.constraint.weakest, limits.min_translation_constraint));
  }
  return {};
}

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <string_view>

#include "core/registration/degeneracy.hpp"

namespace strata {

enum class Verdict { kAccepted, kRejected };

enum class RejectReason {
  kNone,
  kTooFewPairs,    ///< too little overlap to trust: fewer pairs, or a smaller share of the scan, than the
                   ///< limits
  kHighResidual,   ///< the surfaces do not meet: RMSE above the limit
  kJumpFromGuess,  ///< the result lies farther from the guess than odometry can plausibly be wrong
  kDegenerateGeometry,  ///< a direction the paired surfaces do not constrain (corridor, open plane)
};

[[nodiscard]] std::string_view to_string(Verdict verdict);
[[nodiscard]] std::string_view to_string(RejectReason reason);

/// When a registration is not to be trusted. The defaults suit a wheeled robot whose odometry is off by at
/// most a metre and 15 degrees between scans, with the 0.25 m correspondence bound; measured on the real
/// pairs in tests/bench/registration_bench.cpp.
struct FaultLimits {
  std::size_t min_pairs = 100;
  double min_pair_fraction = 0.25;           ///< pairs / downsampled source points
  double max_rmse = 0.15;                    ///< metres
  double max_translation_jump = 1.0;         ///< metres between the guess and the result
  double max_rotation_jump = 0.26;           ///< radians (15 degrees) between the guess and the result
  double min_translation_constraint = 0.01;  ///< smallest eigenvalue of the normalised normal matrix
};

/// The quantities a verdict is made from.
struct RegistrationEvidence {
  std::size_t pairs = 0;
  std::size_t source_points = 0;
  double rmse = 0.0;
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  TranslationConstraint constraint;
};

struct Assessment {
  Verdict verdict = Verdict::kAccepted;
  RejectReason reason = RejectReason::kNone;
  std::string message;  ///< for people: what was measured against which limit
};

/// The first limit the evidence breaks, in order of how fundamental it is; accepted if none.
[[nodiscard]] Assessment assess(const RegistrationEvidence& evidence, const FaultLimits& limits);

}  // namespace strata

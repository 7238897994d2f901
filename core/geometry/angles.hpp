#pragma once

namespace strata {

inline constexpr double kPi = 3.14159265358979323846;

/// Wraps an angle in radians into [-pi, pi).
double wrap_angle(double radians);

}  // namespace strata

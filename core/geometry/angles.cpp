#include "core/geometry/angles.hpp"

#include <cmath>

namespace strata {

double wrap_angle(double radians) {
  if (radians >= -kPi && radians < kPi)
    return radians;  // exact: no rounding through fmod
  double wrapped = std::fmod(radians + kPi, 2.0 * kPi);
  if (wrapped < 0.0)
    wrapped += 2.0 * kPi;
  return wrapped - kPi;
}

}  // namespace strata

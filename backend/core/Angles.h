#pragma once

#include <cmath>

namespace ambler {

// One degree [rad]: angle_deg * kDeg.
inline constexpr double kDeg = M_PI / 180.0;

}  // namespace ambler

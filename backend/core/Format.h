#pragma once

#include <sstream>
#include <string>

namespace ambler {

// `v` with `digits` decimals, for figures in sentences ("0.52 m").
inline std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

}  // namespace ambler

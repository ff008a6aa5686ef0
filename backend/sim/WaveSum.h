#pragma once

#include <vector>

namespace ambler::sim {

struct Wave;

// Waves laid out for vectorised evaluation: sum of a sin(kx x + ky y + phase).
// Built with the vector sine of glibc (libmvec, within 4 ulp): a rough
// ground of thirty waves spends most of a scan's ray casting here.
class WaveSum {
 public:
  explicit WaveSum(const std::vector<Wave>& waves);
  double operator()(double x, double y) const;

 private:
  std::vector<double> kx_, ky_, phase_, amplitude_;
};

}  // namespace ambler::sim

// Compiled with -ffast-math and OpenMP (CMakeLists.txt) so that the loop
// below calls the vector sine; nothing else may live in this file.
#include "sim/WaveSum.h"

#include <cmath>

#include "sim/ProceduralTerrain.h"

namespace ambler::sim {

WaveSum::WaveSum(const std::vector<Wave>& waves) {
  for (const auto& w : waves) {
    kx_.push_back(w.kx);
    ky_.push_back(w.ky);
    phase_.push_back(w.phase);
    amplitude_.push_back(w.amplitude);
  }
}

double WaveSum::operator()(double x, double y) const {
  const double *kx = kx_.data(), *ky = ky_.data(), *phase = phase_.data(), *a = amplitude_.data();
  const int n = int(kx_.size());
  double z = 0.0;
#pragma omp simd reduction(+ : z)
  for (int i = 0; i < n; ++i) z += a[i] * std::sin(kx[i] * x + ky[i] * y + phase[i]);
  return z;
}

}  // namespace ambler::sim

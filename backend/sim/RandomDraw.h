#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "sim/ProceduralTerrain.h"

namespace ambler::sim {

// The seeded random draws the procedural terrains are made from: the same
// seed gives the same terrain on every platform's libstdc++.
class RandomDraw {
 public:
  explicit RandomDraw(std::uint64_t seed) : rng_(seed) {}
  double operator()(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng_); }
  long poisson(double mean) { return std::poisson_distribution<long>(mean)(rng_); }

 private:
  std::mt19937_64 rng_;
};

// Rolling ground: `count` sinusoids in random directions, amplitudes and
// wavelengths drawn from the given ranges [m].
inline std::vector<Wave> rollingGround(RandomDraw& draw, int count, double amp_lo, double amp_hi,
                                       double wavelength_lo, double wavelength_hi) {
  std::vector<Wave> waves;
  for (int i = 0; i < count; ++i) {
    const double k = 2 * M_PI / draw(wavelength_lo, wavelength_hi);
    const double dir = draw(0, 2 * M_PI);
    waves.push_back(
        {draw(amp_lo, amp_hi), k * std::cos(dir), k * std::sin(dir), draw(0, 2 * M_PI)});
  }
  return waves;
}

// Whether `b` comes within `margin` of any box in `taken` (open intervals).
inline bool overlapsAny(const Box2& b, const std::vector<Box2>& taken, double margin = 0.0) {
  for (const auto& t : taken)
    if (b.x_min < t.x_max + margin && b.x_max + margin > t.x_min && b.y_min < t.y_max + margin &&
        b.y_max + margin > t.y_min)
      return true;
  return false;
}

}  // namespace ambler::sim

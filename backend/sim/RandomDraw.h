#pragma once

#include <cstdint>
#include <random>

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

}  // namespace ambler::sim

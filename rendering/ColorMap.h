#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ambler::rendering {

// Viridis: perceptually uniform and readable by colour-blind operators.
// t in [0, 1] (clamped) -> RGB.
std::array<std::uint8_t, 3> viridis(double t);

// Colour of "no data" (no return, unknown) everywhere in the program.
inline constexpr std::array<std::uint8_t, 3> kNoDataColor{40, 40, 40};

// Labels of a colour bar: round values (1, 2 or 5 times a power of ten
// apart) inside [lo, hi], so an operator reads 0.10 m rather than 0.0825 m,
// with as many decimals as their step needs. A bar of one value, or of a
// non-finite range, gets that value alone or nothing.
struct ColorBarTicks {
  std::vector<double> values;  // ascending; exact multiples of the step, so 0 prints "0.00"
  int decimals = 0;
};
[[nodiscard]] ColorBarTicks colorBarTicks(double lo, double hi, int max_count = 7);

}  // namespace ambler::rendering

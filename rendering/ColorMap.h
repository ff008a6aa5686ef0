#pragma once

#include <array>
#include <cstdint>

namespace ambler::rendering {

// Viridis: perceptually uniform and readable by colour-blind operators.
// t in [0, 1] (clamped) -> RGB.
std::array<std::uint8_t, 3> viridis(double t);

// Colour of "no data" (no return, unknown) everywhere in the program.
inline constexpr std::array<std::uint8_t, 3> kNoDataColor{40, 40, 40};

}  // namespace ambler::rendering

#include "rendering/ColorMap.h"

#include <algorithm>
#include <cmath>

namespace ambler::rendering {

std::array<std::uint8_t, 3> viridis(double t) {
  // Nine samples of matplotlib's viridis, linearly interpolated.
  static constexpr double kStops[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                          {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                          {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  const double x = t * 8.0;
  const int i = std::min(int(x), 7);
  const double f = x - i;
  std::array<std::uint8_t, 3> rgb{};
  for (int k = 0; k < 3; ++k)
    rgb[std::size_t(k)] =
        std::uint8_t(std::lround(kStops[i][k] + f * (kStops[i + 1][k] - kStops[i][k])));
  return rgb;
}

}  // namespace ambler::rendering

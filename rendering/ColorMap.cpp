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

ColorBarTicks colorBarTicks(double lo, double hi, int max_count) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return {};
  if (hi - lo <= 1e-12 * std::max(1.0, std::abs(lo))) return {{lo}, 2};
  max_count = std::max(max_count, 2);
  // Fine to coarse from a tenth of the span's share per label: within two
  // decades one of the steps leaves at most max_count labels.
  for (int exponent = int(std::floor(std::log10((hi - lo) / max_count))) - 1;; ++exponent)
    for (const double mantissa : {1.0, 2.0, 5.0}) {
      // k * mantissa / 10^-e rounds to the nearest double of the decimal
      // value (-0.15, not -0.15000000000000002).
      const double ten = std::pow(10.0, std::abs(exponent));
      const auto value = [&](double k) {
        return exponent < 0 ? k * mantissa / ten : k * mantissa * ten;
      };
      const double step = value(1);
      const auto first = std::ceil(lo / step - 1e-9), last = std::floor(hi / step + 1e-9);
      if (last - first + 1 > max_count) continue;
      ColorBarTicks ticks;
      for (double k = first; k <= last; ++k) ticks.values.push_back(k == 0 ? 0.0 : value(k));
      ticks.decimals = std::max(0, -exponent);
      return ticks;
    }
}

}  // namespace ambler::rendering

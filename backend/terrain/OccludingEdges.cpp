#include "terrain/OccludingEdges.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ambler::terrain {

namespace {

// True when the ranges of two pixels with returns, `separation` radians
// apart, cannot belong to one continuous surface. `near_slope` is the range
// change between the nearer pixel and its neighbour on the far side from
// the other pixel (0 when unavailable): an occluder is seen at a steeper
// angle than the jump behind it, while a continuous grazing surface changes
// range at a similar rate on both sides.
struct JumpTest {
  double inv_tan_grazing;
  double step_ratio;
  double noise_sigmas;
  double k;

  bool operator()(double a, double b, double separation, double near_slope) const {
    const double noise = noise_sigmas * k * std::sqrt(a * a * a * a + b * b * b * b);
    const double smooth =
        std::max(std::min(a, b) * separation * inv_tan_grazing, step_ratio * near_slope);
    return std::abs(a - b) > smooth + noise;
  }
};

}  // namespace

OccludingEdges::OccludingEdges(const sensor::RangeImage& image, const OccludingEdgeOptions& options)
    : rows_(image.rows()),
      cols_(image.cols()),
      pixel_(std::size_t(rows_) * cols_, 0),
      quad_(std::size_t(std::max(rows_ - 1, 0)) * std::max(cols_ - 1, 0), 0) {
  const auto& g = image.geometry;
  const JumpTest jumps{1.0 / std::tan(options.min_grazing_deg * M_PI / 180.0), options.step_ratio,
                       options.noise_sigmas, image.range_sigma_k};
  // Angular separation of neighbours: a column step turns the ray by
  // |theta_step|, a row step by |phi_step| cos(theta) (eq. 1).
  const double col_sep = std::abs(g.theta_step);
  std::vector<double> row_sep(cols_), diagonal_sep(cols_);
  for (int c = 0; c < cols_; ++c) {
    row_sep[c] = std::abs(g.phi_step) * std::cos(g.theta(c));
    const double mid = std::abs(g.phi_step) * std::cos(g.theta(c + 0.5));
    diagonal_sep[c] = std::hypot(mid, col_sep);
  }
  // One flag per neighbour pair, each pair tested once.
  const std::size_t n = pixel_.size();
  std::vector<std::uint8_t> right(n, 0), down(n, 0), diagonal(n, 0), anti(n, 0);
  auto valid = [&](int r, int c) {
    return r >= 0 && r < rows_ && c >= 0 && c < cols_ && image.hasReturn(r, c);
  };
  auto test = [&](int r0, int c0, int r1, int c1, double separation) -> std::uint8_t {
    if (!image.hasReturn(r0, c0) || !image.hasReturn(r1, c1)) return 0;
    const double a = image.at(r0, c0), b = image.at(r1, c1);
    const double near = std::min(a, b);
    // Within the grazing bound the pair is continuous whatever the rest of
    // the test says: most pairs, decided without a neighbour or a root.
    if (std::abs(a - b) <= near * separation * jumps.inv_tan_grazing) return 0;
    // The nearer pixel's neighbour on the side away from the other pixel.
    const int dr = r1 - r0, dc = c1 - c0;
    const int nr = a <= b ? r0 - dr : r1 + dr, nc = a <= b ? c0 - dc : c1 + dc;
    const double near_slope = valid(nr, nc) ? std::abs(image.at(nr, nc) - near) : 0.0;
    if (!jumps(a, b, separation, near_slope)) return 0;
    pixel_[std::size_t(r0) * cols_ + c0] = pixel_[std::size_t(r1) * cols_ + c1] = 1;
    return 1;
  };
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      const std::size_t i = std::size_t(r) * cols_ + c;
      if (c + 1 < cols_) right[i] = test(r, c, r, c + 1, col_sep);
      if (r + 1 < rows_) down[i] = test(r, c, r + 1, c, row_sep[c]);
      if (r + 1 < rows_ && c + 1 < cols_) {
        diagonal[i] = test(r, c, r + 1, c + 1, diagonal_sep[c]);
        anti[i] = test(r, c + 1, r + 1, c, diagonal_sep[c]);
      }
    }
  for (int r = 0; r + 1 < rows_; ++r)
    for (int c = 0; c + 1 < cols_; ++c) {
      const std::size_t i = std::size_t(r) * cols_ + c;
      quad_[std::size_t(r) * (cols_ - 1) + c] =
          right[i] | right[i + cols_] | down[i] | down[i + 1] | diagonal[i] | anti[i];
    }
}

int OccludingEdges::edgePixelCount() const {
  return int(std::count(pixel_.begin(), pixel_.end(), std::uint8_t(1)));
}

}  // namespace ambler::terrain

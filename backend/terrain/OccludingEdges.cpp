#include "terrain/OccludingEdges.h"

#include <algorithm>
#include <cmath>

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

// The neighbour pairs of a pixel: to its right, below it, and the two
// diagonals of the quad below and right of it.
enum PairFlags : std::uint8_t { kRight = 1, kDown = 2, kDiagonal = 4, kAnti = 8 };

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
  // The ranges with NaN where there is no return: every comparison with a
  // missing pixel is false, so its pairs are never jumps without a test.
  std::vector<float> range(pixel_.size(), NAN);
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c)
      if (image.hasReturn(r, c)) range[std::size_t(r) * cols_ + c] = image.at(r, c);
  auto at = [&](int r, int c) { return double(range[std::size_t(r) * cols_ + c]); };
  auto test = [&](int r0, int c0, int r1, int c1, double separation) -> std::uint8_t {
    const double a = at(r0, c0), b = at(r1, c1);
    const double near = std::min(a, b);
    // Within the grazing bound the pair is continuous whatever the rest of
    // the test says: most pairs, decided without a neighbour or a root.
    if (!(std::abs(a - b) > near * separation * jumps.inv_tan_grazing)) return 0;
    // The nearer pixel's neighbour on the side away from the other pixel.
    const int dr = r1 - r0, dc = c1 - c0;
    const int nr = a <= b ? r0 - dr : r1 + dr, nc = a <= b ? c0 - dc : c1 + dc;
    const bool valid = nr >= 0 && nr < rows_ && nc >= 0 && nc < cols_ && !std::isnan(at(nr, nc));
    const double near_slope = valid ? std::abs(at(nr, nc) - near) : 0.0;
    if (!jumps(a, b, separation, near_slope)) return 0;
    pixel_[std::size_t(r0) * cols_ + c0] = pixel_[std::size_t(r1) * cols_ + c1] = 1;
    return 1;
  };
  // Each neighbour pair is tested once and marks the quads it belongs to:
  // a row pair the quads above and below it, a column pair those left and
  // right of it, a diagonal its own quad.
  auto quad = [&](int r, int c) -> std::uint8_t& {
    return quad_[std::size_t(r) * (cols_ - 1) + c];
  };
  auto testAll = [&](int r, int c, std::uint8_t candidates) {
    if ((candidates & kRight) && test(r, c, r, c + 1, col_sep)) {
      if (r > 0) quad(r - 1, c) = 1;
      if (r + 1 < rows_) quad(r, c) = 1;
    }
    if ((candidates & kDown) && test(r, c, r + 1, c, row_sep[c])) {
      if (c > 0) quad(r, c - 1) = 1;
      if (c + 1 < cols_) quad(r, c) = 1;
    }
    // Both diagonals are tested: each marks its pixels.
    const bool diagonal = (candidates & kDiagonal) && test(r, c, r + 1, c + 1, diagonal_sep[c]);
    const bool anti = (candidates & kAnti) && test(r, c + 1, r + 1, c, diagonal_sep[c]);
    if (diagonal || anti) quad(r, c) = 1;
  };
  // Screening a row at a time in single precision, in loops the compiler
  // vectorises, finds the few pairs beyond the grazing bound (less 0.1 %,
  // far more than single precision's error); only those get the test.
  const float bound = float(jumps.inv_tan_grazing * 0.999);
  std::vector<float> row_bound(cols_), diagonal_bound(cols_);
  for (int c = 0; c < cols_; ++c) {
    row_bound[c] = float(row_sep[c]) * bound;
    diagonal_bound[c] = float(diagonal_sep[c]) * bound;
  }
  const float col_bound = float(col_sep) * bound;
  auto beyond = [](float a, float b, float bound) {
    return std::abs(a - b) > std::min(a, b) * bound;
  };
  if (cols_ == 0) return;
  std::vector<std::uint8_t> candidates(cols_);
  for (int r = 0; r < rows_; ++r) {
    const float* here = &range[std::size_t(r) * cols_];
    const float* next = r + 1 < rows_ ? here + cols_ : here;  // the last row has no pairs down
    const int last = cols_ - 1;
    for (int c = 0; c < last; ++c)
      candidates[c] = (beyond(here[c], here[c + 1], col_bound) ? kRight : 0) |
                      (beyond(here[c], next[c], row_bound[c]) ? kDown : 0) |
                      (beyond(here[c], next[c + 1], diagonal_bound[c]) ? kDiagonal : 0) |
                      (beyond(here[c + 1], next[c], diagonal_bound[c]) ? kAnti : 0);
    candidates[last] = beyond(here[last], next[last], row_bound[last]) ? kDown : 0;
    if (r + 1 == rows_)
      for (auto& flags : candidates) flags &= kRight;
    for (int c = 0; c < cols_; ++c)
      if (candidates[c]) testAll(r, c, candidates[c]);
  }
}

int OccludingEdges::edgePixelCount() const {
  return int(std::count(pixel_.begin(), pixel_.end(), std::uint8_t(1)));
}

}  // namespace ambler::terrain

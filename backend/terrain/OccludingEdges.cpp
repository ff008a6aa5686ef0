#include "terrain/OccludingEdges.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::terrain {

namespace {

// What a pair of pixels is. The weak levels are beyond only the smaller,
// hysteresis allowance; they count when the same kind of pair beside them
// along the image is an edge or grazing.
enum Level : std::uint8_t { kContinuous, kWeakEdge, kEdge, kGrazing, kWeakGrazing };

// The level of two pixels with returns, `separation` radians apart: whether
// their ranges can belong to one continuous surface. `near_slope` is the
// range change between the nearer pixel and its neighbour on the far side
// from the other pixel (0 when unavailable): an occluder is seen at a
// steeper angle than the jump behind it, while a continuous grazing surface
// changes range at a similar rate on both sides.
struct JumpTest {
  double inv_tan_grazing;
  double inv_tan_weak_grazing;  // at most inv_tan_grazing
  double step_ratio;
  double noise_sigmas;
  double k;

  double weak_sigmas;  // at most noise_sigmas
  double grazing_sigmas;
  double weak_grazing_sigmas;  // at most grazing_sigmas

  // Std. dev. of the jump between two ranges, each with noise k rho^2.
  double jumpSigma(double a, double b) const {
    return k * std::sqrt(a * a * a * a + b * b * b * b);
  }

  Level operator()(double a, double b, double separation, double near_slope) const {
    const double sigma = jumpSigma(a, b);
    const double grazing = std::min(a, b) * separation * inv_tan_grazing;
    const double smooth = std::max(grazing, step_ratio * near_slope);
    const double jump = std::abs(a - b);
    if (jump > smooth + noise_sigmas * sigma) return kEdge;
    if (jump > smooth + weak_sigmas * sigma) return kWeakEdge;
    if (jump > grazing + grazing_sigmas * sigma) return kGrazing;
    const double weak_grazing = std::min(a, b) * separation * inv_tan_weak_grazing;
    return jump > grazing + weak_grazing_sigmas * sigma ||
                   jump > weak_grazing + grazing_sigmas * sigma
               ? kWeakGrazing
               : kContinuous;
  }
};

// The neighbour pairs of a pixel: to its right, below it, and the two
// diagonals of the quad below and right of it.
enum PairFlags : std::uint8_t { kRight = 1, kDown = 2, kDiagonal = 4, kAnti = 8 };

// Throws std::invalid_argument naming the allowance out of order, or the
// weak grazing angle out of range; returns the weak edge allowance, at
// most the strong one.
double checkedWeakSigmas(const OccludingEdgeOptions& options) {
  // An uncontinued weak jump counts as grazing, which is only right when it
  // is beyond the grazing allowance too.
  const double weak_sigmas = std::min(options.weak_noise_sigmas, options.noise_sigmas);
  auto requireAtMost = [&](double sigmas, const char* what, double limit, const char* limit_what) {
    if (options.mark_grazing && sigmas > limit)
      throw std::invalid_argument(std::string("the ") + what + " noise allowance (" +
                                  std::to_string(sigmas) + " sigma) must not exceed the " +
                                  limit_what + " allowance (" + std::to_string(limit) + " sigma)");
  };
  requireAtMost(options.grazing_noise_sigmas, "grazing", weak_sigmas, "weak edge");
  requireAtMost(options.weak_grazing_noise_sigmas, "weak grazing", options.grazing_noise_sigmas,
                "grazing");
  if (!(options.weak_grazing_deg > 0 && options.weak_grazing_deg < 90))
    throw std::invalid_argument("the weak grazing angle must lie between 0 and 90 degrees, not " +
                                std::to_string(options.weak_grazing_deg));
  if (!(options.concave_turn_deg >= 0 && options.concave_turn_deg < 90))
    throw std::invalid_argument("the concave turn must lie between 0 (off) and 90 degrees, not " +
                                std::to_string(options.concave_turn_deg));
  if (!(options.grazing_baseline_noise_sigmas >= 0))
    throw std::invalid_argument("the grazing baseline's noise allowance must be >= 0 sigma");
  if (options.grazing_baseline_rows < 0 || options.grazing_baseline_rows == 1)
    throw std::invalid_argument(
        "the grazing baseline must be 0 (off) or at least 2 scanlines, not " +
        std::to_string(options.grazing_baseline_rows));
  return weak_sigmas;
}

// The level of every pair of neighbouring pixels, three bits per kind of
// pair (right, down, diagonal, anti) by the pixel it starts from.
class PairLevels {
 public:
  PairLevels(const sensor::RangeImage& image, const JumpTest& jumps)
      : rows_(image.rows()), cols_(image.cols()), jumps_(jumps) {
    // Angular separation of neighbours: a column step turns the ray by
    // |theta_step|, a row step by |phi_step| cos(theta) (eq. 1).
    const auto& g = image.geometry;
    col_sep_ = std::abs(g.theta_step);
    row_sep_.resize(cols_), diagonal_sep_.resize(cols_);
    for (int c = 0; c < cols_; ++c) {
      row_sep_[c] = std::abs(g.phi_step) * std::cos(g.theta(c));
      const double mid = std::abs(g.phi_step) * std::cos(g.theta(c + 0.5));
      diagonal_sep_[c] = std::hypot(mid, col_sep_);
    }
    // The ranges with NaN where there is no return: every comparison with
    // a missing pixel is false, so its pairs are never jumps without a test.
    range_.assign(std::size_t(rows_) * cols_, NAN);
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c)
        if (image.hasReturn(r, c)) range_[std::size_t(r) * cols_ + c] = image.at(r, c);
    level_.assign(range_.size(), 0);
    if (cols_ > 0) screen();
  }

  const std::vector<float>& range() const { return range_; }
  const std::vector<double>& rowSeparation() const { return row_sep_; }
  // Any pair from this pixel beyond the continuous level.
  bool any(int r, int c) const { return level_[std::size_t(r) * cols_ + c] != 0; }
  Level at(int r, int c, int kind) const {
    if (r < 0 || c < 0 || r >= rows_ || c >= cols_) return kContinuous;
    return Level((level_[std::size_t(r) * cols_ + c] >> (3 * kind)) & 7);
  }
  // The pair across scanlines (r, r + 1) at column c, seen under the weak
  // grazing angle beyond `sigmas` of its noise, against the next such pair
  // farther from the sensor: whether that one is seen more steeply by the
  // turn (`tan_turn` its tangent), beyond `sigmas` of its jump's noise (a
  // steeper pair has the smaller jump). NaN (no return) is no turn.
  bool turnsBackBeyond(int r, int c, double tan_turn, double sigmas) const {
    const double a = rangeAt(r, c), b = rangeAt(r + 1, c);
    const double weak = std::min(a, b) * row_sep_[c] * jumps_.inv_tan_weak_grazing;
    if (!(std::abs(a - b) > weak + sigmas * jumps_.jumpSigma(a, b))) return false;
    const int f = a > b ? r - 1 : r + 1;  // the farther pair is (f, f + 1)
    if (f < 0 || f + 1 >= rows_) return false;
    const double x = rangeAt(f, c), y = rangeAt(f + 1, c);
    // 1 / tan(seen + turn) from tan(seen) = near * separation / jump; none
    // steeper exists when seen + turn reaches 90 degrees.
    const double tan_seen = std::min(a, b) * row_sep_[c] / std::abs(a - b);
    const double cot_turned = (1 - tan_seen * tan_turn) / (tan_seen + tan_turn);
    const double steeper_jump = std::min(x, y) * row_sep_[c] * cot_turned;
    return std::abs(x - y) + sigmas * jumps_.jumpSigma(x, y) < steeper_jump;
  }
  // A weak level is kept when what it is continues: a pair of the same
  // kind beside it along the run (across rows for a row pair, along columns
  // for a column pair, either way for diagonals) whose level `counts`.
  template <class Counts>
  bool continued(int r, int c, int kind, Counts counts) const {
    for (int d = -1; d <= 1; ++d)
      for (int e : {-1, 1}) {
        const bool along_columns = kind == 1 || (kind >= 2 && d == 0);
        const int rr = along_columns ? r + d : r + e, cc = along_columns ? c + e : c + d;
        if (counts(at(rr, cc, kind))) return true;
      }
    return false;
  }

 private:
  double rangeAt(int r, int c) const { return double(range_[std::size_t(r) * cols_ + c]); }

  Level test(int r0, int c0, int r1, int c1, double separation) const {
    const double a = rangeAt(r0, c0), b = rangeAt(r1, c1);
    const double near = std::min(a, b);
    // Within the weak grazing bound (the grazing bound's or nearer) the pair
    // is continuous whatever the rest of the test says: most pairs, decided
    // without a neighbour or a root.
    if (!(std::abs(a - b) > near * separation * jumps_.inv_tan_weak_grazing)) return kContinuous;
    // The nearer pixel's neighbour on the side away from the other pixel.
    const int dr = r1 - r0, dc = c1 - c0;
    const int nr = a <= b ? r0 - dr : r1 + dr, nc = a <= b ? c0 - dc : c1 + dc;
    const bool valid =
        nr >= 0 && nr < rows_ && nc >= 0 && nc < cols_ && !std::isnan(rangeAt(nr, nc));
    const double near_slope = valid ? std::abs(rangeAt(nr, nc) - near) : 0.0;
    return jumps_(a, b, separation, near_slope);
  }

  void record(int r, int c, int kind, Level l) {
    level_[std::size_t(r) * cols_ + c] |= std::uint16_t(l << (3 * kind));
  }

  void testAll(int r, int c, std::uint8_t candidates) {
    if (candidates & kRight) record(r, c, 0, test(r, c, r, c + 1, col_sep_));
    if (candidates & kDown) record(r, c, 1, test(r, c, r + 1, c, row_sep_[c]));
    if (candidates & kDiagonal) record(r, c, 2, test(r, c, r + 1, c + 1, diagonal_sep_[c]));
    if (candidates & kAnti) record(r, c, 3, test(r, c + 1, r + 1, c, diagonal_sep_[c]));
  }

  // Screening a row at a time in single precision, in loops the compiler
  // vectorises, finds the few pairs beyond the weak grazing bound (less
  // 0.1 %, far more than single precision's error); only those get the
  // test.
  void screen() {
    const float bound = float(jumps_.inv_tan_weak_grazing * 0.999);
    std::vector<float> row_bound(cols_), diagonal_bound(cols_);
    for (int c = 0; c < cols_; ++c) {
      row_bound[c] = float(row_sep_[c]) * bound;
      diagonal_bound[c] = float(diagonal_sep_[c]) * bound;
    }
    const float col_bound = float(col_sep_) * bound;
    auto beyond = [](float a, float b, float bound) {
      return std::abs(a - b) > std::min(a, b) * bound;
    };
    std::vector<std::uint8_t> candidates(cols_);
    for (int r = 0; r < rows_; ++r) {
      const float* here = &range_[std::size_t(r) * cols_];
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

  int rows_, cols_;
  JumpTest jumps_;
  double col_sep_ = 0.0;
  std::vector<double> row_sep_, diagonal_sep_;
  std::vector<float> range_;
  std::vector<std::uint16_t> level_;
};

}  // namespace

OccludingEdges::OccludingEdges(const sensor::RangeImage& image, const OccludingEdgeOptions& options)
    : rows_(image.rows()),
      cols_(image.cols()),
      pixel_(std::size_t(rows_) * cols_, 0),
      quad_(std::size_t(std::max(rows_ - 1, 0)) * std::max(cols_ - 1, 0), 0) {
  const double weak_sigmas = checkedWeakSigmas(options);
  const double inv_tan_grazing = 1.0 / std::tan(options.min_grazing_deg * M_PI / 180.0);
  const JumpTest jumps{
      inv_tan_grazing,
      std::min(inv_tan_grazing, 1.0 / std::tan(options.weak_grazing_deg * M_PI / 180.0)),
      options.step_ratio,
      options.noise_sigmas,
      image.range_sigma_k,
      weak_sigmas,
      options.grazing_noise_sigmas,
      options.weak_grazing_noise_sigmas};
  if (cols_ == 0) return;
  const PairLevels levels(image, jumps);
  if (options.mark_grazing && options.grazing_baseline_rows > 0)
    markGrazingBaselines(levels.range(), levels.rowSeparation(), jumps.inv_tan_grazing, jumps.k,
                         options.grazing_baseline_rows, options.grazing_baseline_noise_sigmas,
                         options.grazing_noise_sigmas);
  auto isEdge = [](Level l) { return l == kWeakEdge || l == kEdge; };
  auto isEdgeOrGrazing = [](Level l) { return l == kWeakEdge || l == kEdge || l == kGrazing; };
  const double tan_turn = std::tan(options.concave_turn_deg * M_PI / 180.0);
  auto weakGrazingCounts = [&](int r, int c, int kind) {
    return levels.continued(r, c, kind, isEdgeOrGrazing) ||
           (kind == 1 && tan_turn > 0 &&
            levels.turnsBackBeyond(r, c, tan_turn, options.grazing_noise_sigmas));
  };
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      if (!levels.any(r, c)) continue;
      for (int kind = 0; kind < 4; ++kind) {
        const Level l = levels.at(r, c, kind);
        if (l == kContinuous) continue;
        if (l == kGrazing || l == kWeakGrazing ||
            (l == kWeakEdge && !levels.continued(r, c, kind, isEdge))) {
          if (options.mark_grazing && (l != kWeakGrazing || weakGrazingCounts(r, c, kind)))
            markQuadsOfPair(r, c, kind, kGrazingQuad);
          continue;
        }
        markEdgePair(r, c, kind);
      }
    }
}

// An occluding edge between the two pixels of a pair: both are edge
// pixels, and it marks its quads.
void OccludingEdges::markEdgePair(int r, int c, int kind) {
  const int r1 = kind == 0 ? r : r + 1;
  const int c0 = kind == 3 ? c + 1 : c, c1 = kind == 1 ? c : (kind == 3 ? c : c + 1);
  pixel_[std::size_t(r) * cols_ + c0] |= kEdgePixel;
  pixel_[std::size_t(r1) * cols_ + c1] |= kEdgePixel;
  if (kind == 0) pixel_[std::size_t(r) * cols_ + c] |= kRightPairEdge;
  markQuadsOfPair(r, c, kind, kEdgeQuad);
}

// Each pair of scanlines (r, r + 1) against the range step per scanline
// averaged over the `rows` scanlines around it, from the difference of its
// two ends: the pixels between drop out, and so does most of their noise
// (std. dev. k sqrt(a^4 + b^4) / (rows - 1)). Only where the pair alone
// cannot rule grazing out (within `pair_noise_sigmas` of the bound): without
// noise its own test is exact. Squares stand for the roots, and single
// precision for double, so that the loop over a scanline vectorises.
void OccludingEdges::markGrazingBaselines(const std::vector<float>& range,
                                          const std::vector<double>& row_sep,
                                          double inv_tan_grazing, double k, int rows,
                                          double noise_sigmas, double pair_noise_sigmas) {
  const int half = rows / 2, span = 2 * half - 1;
  std::vector<float> bound_per_rho(cols_);
  for (int c = 0; c < cols_; ++c) bound_per_rho[c] = float(row_sep[c] * inv_tan_grazing);
  const float inv_span = 1.0f / float(span);
  const float pair_var = float(pair_noise_sigmas * pair_noise_sigmas * k * k);
  const float mean_var = float(noise_sigmas * noise_sigmas * k * k) * inv_span * inv_span;
  std::vector<std::uint8_t> hit(cols_);
  for (int r = half - 1; r + half < rows_; ++r) {
    const float* first = &range[std::size_t(r - half + 1) * cols_];
    const float* last = &range[std::size_t(r + half) * cols_];
    const float* upper = &range[std::size_t(r) * cols_];
    const float* lower = upper + cols_;
    for (int c = 0; c < cols_; ++c) {
      const float a = first[c], b = last[c], u = upper[c], l = lower[c];
      const float bound = std::min(u, l) * bound_per_rho[c];
      const float short_of = bound - std::abs(u - l);
      const float u2 = u * u, l2 = l * l, a2 = a * a, b2 = b * b;
      const bool undecided =
          (short_of < 0) | (short_of * short_of < pair_var * (u2 * u2 + l2 * l2));
      const float beyond = std::abs(b - a) * inv_span - bound;
      // Comparisons with NaN (no return) are false.
      hit[c] = undecided & (beyond > 0) & (beyond * beyond > mean_var * (a2 * a2 + b2 * b2));
    }
    for (int c = 0; c < cols_; ++c)
      if (hit[c]) markQuadsOfPair(r, c, 1, kGrazingQuad);
  }
}

// A pair marks the quads it belongs to: a pair along a scanline the quads
// above and below it, a pair across scanlines those left and right of it,
// a diagonal its own quad.
void OccludingEdges::markQuadsOfPair(int r, int c, int kind, std::uint8_t flag) {
  auto set = [&](int qr, int qc) { quad_[std::size_t(qr) * (cols_ - 1) + qc] |= flag; };
  if (kind == 0) {
    if (r > 0) set(r - 1, c);
    if (r + 1 < rows_) set(r, c);
  } else if (kind == 1) {
    if (c > 0) set(r, c - 1);
    if (c + 1 < cols_) set(r, c);
  } else {
    set(r, c);
  }
}

int OccludingEdges::edgePixelCount() const {
  return int(std::count_if(pixel_.begin(), pixel_.end(),
                           [](std::uint8_t p) { return (p & kEdgePixel) != 0; }));
}

}  // namespace ambler::terrain

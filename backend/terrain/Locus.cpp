#include "terrain/Locus.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "terrain/LocusTables.h"
#include "terrain/PixelTable.h"

namespace ambler::terrain {

namespace {

using sensor::RangeImage;

// The vertical world line through (x, y) in the sensor frame: a + t b, where
// t is the world height of the point [m].
struct Line {
  Eigen::Vector3d a;
  Eigen::Vector3d b;
};

// Where the line crosses the half-plane of scan angle phi (eq. 2 for a
// general line): its height, range rho_I(phi) and fractional column.
struct LocusPoint {
  bool on_image = false;
  double t = 0.0;
  double rho = 0.0;
  double col = 0.0;
};

// Delta(phi_j) of the paper at one scanline, with the locus point.
struct RowSample {
  bool ok = false;  // on the image, nearest pixel has a return
  int row = 0;
  LocusPoint at;
  double delta = 0.0;  // rho_I - I at the nearest column [m]
};

// Two adjacent scanlines between which the line goes behind the surface,
// and the scanlines just beyond them, where sampled (sigmaOfHeight()).
struct Bracket {
  RowSample upper;  // the line in front of the surface (Delta < 0)
  RowSample lower;  // the line behind it
  RowSample above, below;
};

// What the range noise does to a cell's height.
struct HeightNoise {
  double sigma = INFINITY;  // [m]
  // Height change per range change at the crossing, |dt/drow| / |dDelta/drow|.
  double height_per_range = 0.0;
  // The slope of Delta across the bracket is significant against the noise.
  bool significant = false;
  // Delta stays within the noise beyond the bracket, or its slope is not
  // significant: the crossing may be one of several.
  bool ambiguous = false;
};

struct CellResult {
  CellState state = CellState::kUnknown;
  // Known or oblique: the cell's height. Shadow: the height of the line where the
  // search stopped, at the occluder's silhouette, where the next cell's
  // search starts (else every cell of a shadow walks up from the ground).
  double z = NAN;
  double sigma = 0.0;  // noise and sampling together [m]
  HeightNoise noise{};
  // Unknown because the line's first point is off the image: the cell is
  // out of the field of view.
  bool out_of_view = false;
  // The fractional image row where the line met the surface; NaN where the
  // walk found no crossing.
  double row = NAN;
  // Shadow, but within a stretch where nothing tells whether it is: beyond
  // the occluder's last sample (LocusOptions::undecided_before_shadow), at
  // a crest's shadow's far end, or in a border pixel's footprint (walk()).
  // Unknown once the shadow's sides are marked.
  bool undecided = false;
  // Along a face, where the height is the middle of the band in which the
  // line runs within the noise of the surface: sigma without the band.
  // NaN elsewhere.
  double face_noise = NAN;
};

// The heights of the line over which Delta is within the noise of zero.
struct Band {
  double top = -INFINITY, bottom = INFINITY;
  // Least-squares line of Delta over the band's scanlines.
  double n = 0, sum_row = 0, sum_row2 = 0, sum_delta = 0, sum_row_delta = 0;

  double height() const { return top > bottom ? top - bottom : 0.0; }
  void add(int row, double t, double delta) {
    top = std::max(top, t), bottom = std::min(bottom, t);
    n += 1, sum_row += row, sum_row2 += double(row) * row;
    sum_delta += delta, sum_row_delta += row * delta;
  }
  void merge(const Band& o) {
    top = std::max(top, o.top), bottom = std::min(bottom, o.bottom);
    n += o.n, sum_row += o.sum_row, sum_row2 += o.sum_row2;
    sum_delta += o.sum_delta, sum_row_delta += o.sum_row_delta;
  }
  // The band's height that noise of `pixel_sigma` explains where Delta
  // keeps the slope it has across the band: the scanlines over which it
  // stays within +-3 sigma, times the line's height change per scanline;
  // 0 when the slope is not significant there (a face runs along the line).
  double explainedByNoise(double pixel_sigma, double height_per_row) const {
    if (n < 3) return 0.0;
    const double spread = sum_row2 - sum_row * sum_row / n;
    const double slope = (sum_row_delta - sum_row * sum_delta / n) / spread;
    if (!(std::abs(slope) * std::sqrt(spread) > 3 * pixel_sigma)) return 0.0;
    return 6 * pixel_sigma / std::abs(slope) * height_per_row;
  }
};

// Over the image's columns and half a pixel beyond.
PixelTable columnTable(const sensor::ScanGeometry& g) {
  const double a = g.theta(-1.5), b = g.theta(g.cols + 0.5);
  const double lo = std::max(std::min(a, b), -1.5), hi = std::min(std::max(a, b), 1.5);
  return PixelTable(std::tan(lo), std::tan(hi),
                    [&](double tan_theta) { return g.col(std::atan(tan_theta)); });
}

// Over the image's rows and half a row beyond; none (atan2 instead) for an
// image more than 170 degrees tall.
PixelTable rowTable(const sensor::ScanGeometry& g) {
  const double mid = g.phi((g.rows - 1) / 2.0);
  const double a = g.phi(-1.5) - mid, b = g.phi(g.rows + 0.5) - mid;
  if (std::max(std::abs(a), std::abs(b)) > 1.5) return PixelTable();
  return PixelTable(std::tan(std::min(a, b)), std::tan(std::max(a, b)),
                    [&](double tan_phi) { return g.row(mid + std::atan(tan_phi)); });
}

class LocusSolver {
 public:
  LocusSolver(const RangeImage& image, const OccludingEdges& edges, double epsilon_rad,
              const LocusOptions& options);

  // Median world height of the image's points (every 4th row and column):
  // where the search of the first cell of each map row starts.
  double typicalHeight() const { return tables_.typicalHeight(); }

  // Starts the search at image row `row_hint`, where the neighbouring
  // cell's line met the surface, or if that is NaN where the line is at
  // height `z_guess` (which takes an inverse tangent).
  CellResult solve(double x, double y, double z_guess, double row_hint) const;
  // Whether the search for the cell at (x, y) would start on the image:
  // solve()'s first step alone.
  bool startsInView(double x, double y, double z_guess) const;

 private:
  LocusPoint pointAt(const Line& line, int row) const;
  RowSample sampleRow(const Line& line, int row) const;
  RowSample sampleRowAt(const Line& line, int row, double col) const;
  void compareWithImage(RowSample& s) const;
  int startRow(const Line& line, double z) const;
  // Fills `end` (z where the search stopped, out of view, undecided) unless
  // the line met the surface, in the bracket.
  CellState walk(const Line& line, int down, int row, Bracket& bracket, CellResult& end) const;
  Line lineThrough(double x, double y) const {
    return {world_to_sensor_ * (Eigen::Vector3d(x, y, 0.0) - origin_), b_};
  }
  CellResult refine(const Line& line, Bracket& br) const;
  CellResult finish(const Line& line, Bracket& br, double t, double u, double col,
                    int quad_col) const;
  Band followBand(const Line& line, int down, const Bracket& br) const;
  double rangeAt(int upper, int lower, double u, double col, int& quad_col) const;
  double rowCurvatureShift(const Bracket& br, double u, double col, int quad_col) const;
  double noiseOfRange(int upper, int lower, double u, double col) const;
  double imageRangeOnRow(int row, double col) const;
  bool passesInFreeSpace(const RowSample& n) const;
  int firstReturnBelow(const Line& line, int down, RowSample s) const;
  CellState hiddenBelowFreeSpace(RowSample n, double hidden_t, double& stop_t) const;
  HeightNoise sigmaOfHeight(const Line& line, Bracket& br, double u, double col,
                            int quad_col) const;
  struct Jump;
  Jump jumpAt(int quad_row, double col) const;
  bool isUndecided(const Line& line, int quad_row, double col) const;
  double shadowFarEndFrom(const Jump& jump) const;
  double reachAt(int row, int col) const {
    return tables_.reach()[std::size_t(row) * g_.cols + col];
  }
  // The horizontal distance from the sensor to the line, whose foot is the
  // sensor's origin plus the turned a.
  double reachOf(const Line& line) const {
    return (world_to_sensor_.transpose() * line.a).head<2>().norm();
  }
  double columnOf(double tan_theta) const;
  double rowOf(double y, double z) const;

  const RangeImage& image_;
  const LocusTables tables_;
  const OccludingEdges& edges_;
  const sensor::ScanGeometry& g_;
  double undecided_steps_ = 0.0;  // LocusOptions::undecided_before_shadow
  double far_end_share_ = 0.0;    // LocusOptions::undecided_shadow_far_end
  double cos_crest_ = 1.0;        // cos(LocusOptions::crest_max_angle_deg)
  // Beyond this range a quad's noise may hide a gap (LocusOptions::
  // max_gap_hidden_by_noise_m) [m].
  double max_sure_range_ = INFINITY;
  Eigen::Matrix3d world_to_sensor_;
  Eigen::Vector3d origin_, b_;
  const double *sin_phi_, *cos_phi_;  // per scanline (LocusTables::sinPhi(), cosPhi())
  // 1 / (b_z cos(phi) - b_y sin(phi)) per scanline: every line shares the
  // direction b, so the denominator of eq. 2 depends on the scanline only.
  // NaN for a scanline whose plane holds b: every line point on it is NaN,
  // and so off the image, without a test.
  std::vector<double> inverse_den_;
  // The image's ranges with NaN where a pixel has no return
  // (LocusTables::ranges()).
  const double* range_ = nullptr;
  const double* row_curvature_ = nullptr;  // LocusTables::rowCurvature()
  // Bisection halves the step from one scanline to the next at each level;
  // sin and cos of those half steps turn phi without calling sin/cos.
  std::vector<double> sin_half_, cos_half_;
  // Column as a function of tan(theta).
  PixelTable column_table_;
  // Row as a function of tan(phi - phi_mid), phi_mid the middle scanline:
  // the image spans less than 180 degrees about it.
  double sin_mid_ = 0.0, cos_mid_ = 1.0;
  PixelTable row_table_;
  double last_col_ = 0.0;  // the image's right border, cols - 0.5
};

LocusSolver::LocusSolver(const RangeImage& image, const OccludingEdges& edges, double epsilon_rad,
                         const LocusOptions& options)
    : image_(image),
      tables_(image, edges, options.max_sample_spacing_m, options.curved_between_scanlines),
      edges_(edges),
      g_(image.geometry),
      undecided_steps_(options.undecided_before_shadow),
      far_end_share_(options.undecided_shadow_far_end),
      cos_crest_(std::cos(options.crest_max_angle_deg * M_PI / 180)),
      sin_phi_(tables_.sinPhi().data()),
      cos_phi_(tables_.cosPhi().data()),
      range_(tables_.ranges().data()),
      row_curvature_(tables_.rowCurvature().data()),
      column_table_(columnTable(image.geometry)),
      row_table_(rowTable(image.geometry)) {
  world_to_sensor_ = image.sensor_to_world.linear().transpose();
  b_ = world_to_sensor_ * Eigen::Vector3d::UnitZ();
  origin_ = image.sensor_to_world.translation();
  max_sure_range_ = rangeWhereNoiseMayHideGap(image.range_sigma_k, options);
  for (int r = 0; r < g_.rows; ++r) {
    const double den = b_.z() * cos_phi_[r] - b_.y() * sin_phi_[r];
    inverse_den_.push_back(std::abs(den) < 1e-12 ? NAN : 1.0 / den);
  }
  last_col_ = g_.cols - 0.5;
  sin_mid_ = std::sin(g_.phi((g_.rows - 1) / 2.0));
  cos_mid_ = std::cos(g_.phi((g_.rows - 1) / 2.0));
  // One level per halving until the bracket is narrower than epsilon.
  for (double h = std::abs(g_.phi_step) / 2; 2 * h > epsilon_rad; h /= 2) {
    sin_half_.push_back(std::sin(h));
    cos_half_.push_back(std::cos(h));
  }
}

// Linear interpolation in a table of 4096 intervals of tan(theta) over the
// image's columns; kept only if it matches atan to 1e-4 pixel everywhere
// (it does unless the image reaches within a few degrees of theta = 90).
double LocusSolver::columnOf(double tan_theta) const {
  if (column_table_.empty()) return g_.col(std::atan(tan_theta));
  return column_table_(tan_theta);  // NaN beyond the table: off the image
}

// The fractional row of direction (y, z) in the sensor's y-z plane; atan2
// more than 90 degrees from the middle scanline or without a table. Beyond
// the table the direction is off the image, where startRow() only needs to
// know on which side: a quarter of the calls, 0.5 ms of a map with atan2.
double LocusSolver::rowOf(double y, double z) const {
  const double y_mid = y * cos_mid_ + z * sin_mid_, z_mid = z * cos_mid_ - y * sin_mid_;
  if (y_mid > 0 && !row_table_.empty()) {
    const double tan_phi = z_mid / y_mid, row = row_table_(tan_phi);
    return std::isnan(row) ? row_table_.extrapolated(tan_phi) : row;
  }
  return g_.row(std::atan2(z, y));
}

bool LocusSolver::startsInView(double x, double y, double z_guess) const {
  const Line line = lineThrough(x, y);
  return pointAt(line, startRow(line, z_guess)).on_image;
}

CellResult LocusSolver::solve(double x, double y, double z_guess, double row_hint) const {
  const Line line = lineThrough(x, y);
  // Which row step lowers the line point: dt/dphi has the sign of
  // (a_y b_z - a_z b_y) between the poles of eq. 2.
  const double turn = line.a.y() * line.b.z() - line.a.z() * line.b.y();
  const int down = (turn * g_.phi_step < 0) ? 1 : -1;
  Bracket bracket;
  const int start = std::isnan(row_hint) ? startRow(line, z_guess) : int(row_hint + 0.5);
  CellResult end;
  const auto found = walk(line, down, start, bracket, end);
  if (found != CellState::kKnown) {
    end.state = found;
    return end;
  }
  auto result = refine(line, bracket);
  if (!hasHeight(result.state) || !result.noise.ambiguous) return result;
  // A line running beside a vertical face stays within the noise of the
  // surface over a long stretch, so Delta may change sign anywhere along it:
  // the surface may be at either end (the face's foot or its top). Noise
  // alone explains a band of 6 pixel sigmas (the band's test) through the
  // slope of Delta: the crossing's, or the band's own, which more
  // scanlines measure better where the noise is large (far ground). Beyond
  // that, the cell's height is the band's middle, give or take half the
  // band.
  const Band band = followBand(line, down, bracket);
  const double pixel_sigma = sensor::rangeSigma(bracket.upper.at.rho, image_.range_sigma_k);
  const double by_crossing =
      result.noise.significant ? 6 * pixel_sigma * result.noise.height_per_range : 0.0;
  // The band's own slope (two divisions and a root) only where the
  // crossing's does not explain the band already, as it mostly does.
  if (band.height() <= by_crossing) return result;
  const double height_per_row = std::abs(bracket.lower.at.t - bracket.upper.at.t);
  const double excess =
      band.height() - std::max(by_crossing, band.explainedByNoise(pixel_sigma, height_per_row));
  if (excess > 0) {
    result.face_noise = result.sigma;
    result.z = 0.5 * (band.top + band.bottom);
    result.sigma = std::sqrt(result.sigma * result.sigma + excess * excess / 12);
  }
  return result;
}

// Inlined, as is sampleRow(): about 500k calls per map, and the calls and
// their returned structs cost a tenth of the run.
[[gnu::always_inline]] inline LocusPoint LocusSolver::pointAt(const Line& line, int row) const {
  LocusPoint lp;
  const double sin_phi = sin_phi_[row], cos_phi = cos_phi_[row];
  lp.t = (line.a.y() * sin_phi - line.a.z() * cos_phi) * inverse_den_[row];
  const Eigen::Vector3d p = line.a + lp.t * line.b;
  // p's distance from the sensor's x axis, negative in the opposite
  // half-plane; tan(theta) from it needs no square root.
  const double across = p.y() * cos_phi + p.z() * sin_phi;
  if (across <= 0) return lp;
  lp.col = columnOf(p.x() / across);
  lp.on_image = lp.col > -0.5 && lp.col < last_col_;
  // The square root only for a point on the image: most of the cells out
  // of view stop here.
  if (lp.on_image) lp.rho = p.norm();
  return lp;
}

[[gnu::always_inline]] inline RowSample LocusSolver::sampleRow(const Line& line, int row) const {
  RowSample s;
  s.row = row;
  s.at = pointAt(line, row);
  if (s.at.on_image) compareWithImage(s);
  return s;
}

// Delta at a sample on the image. The image's range is interpolated
// between the two nearest columns rather than the paper's nearest column,
// so that the bracket agrees with the bilinear surface the binary search
// uses (else a root just past a scanline can fall outside the bracket and
// the search stops at its end).
[[gnu::always_inline]] inline void LocusSolver::compareWithImage(RowSample& s) const {
  s.delta = s.at.rho - imageRangeOnRow(s.row, s.at.col);
  s.ok = std::isfinite(s.delta);  // NaN without returns, or on a scanline parallel to the line
}

// sampleRow() where the column is known beforehand: no division and no
// table on the way to the image's range, the samples' longest chain.
[[gnu::always_inline]] inline RowSample LocusSolver::sampleRowAt(const Line& line, int row,
                                                                 double col) const {
  RowSample s;
  s.row = row;
  const double sin_phi = sin_phi_[row], cos_phi = cos_phi_[row];
  s.at.t = (line.a.y() * sin_phi - line.a.z() * cos_phi) * inverse_den_[row];
  const Eigen::Vector3d p = line.a + s.at.t * line.b;
  s.at.col = col;
  s.at.on_image = p.y() * cos_phi + p.z() * sin_phi > 0 && col > -0.5 && col < last_col_;
  if (!s.at.on_image) return s;
  s.at.rho = p.norm();
  compareWithImage(s);
  return s;
}

// A row sample on the image whose nearest pixel has no return, nearer than
// the sensor reaches: the ray went past the line point without a hit.
bool LocusSolver::passesInFreeSpace(const RowSample& n) const {
  if (!n.at.on_image || !(n.at.rho < tables_.farthestReturn())) return false;
  const int c = std::clamp(int(n.at.col + 0.5), 0, g_.cols - 1);
  return std::isnan(range_[std::size_t(n.row) * g_.cols + c]);
}

// The row of the first sample with a return down the line from one in free
// space, or -1. Out of line, as is hiddenBelowFreeSpace: both are rare,
// and kept off walk()'s path.
[[gnu::noinline]] int LocusSolver::firstReturnBelow(const Line& line, int down, RowSample s) const {
  for (int row = s.row + down; passesInFreeSpace(s) && row >= 0 && row < g_.rows; row += down) {
    s = sampleRow(line, row);
    if (s.ok) return row;
  }
  return -1;
}

// The line is hidden at height `hidden_t` and `n`, the next sample up, has
// no return: if n's ray passed the line in free space, the ground lies
// lower, for on a height field all of a line below a hidden point is
// hidden too.
[[gnu::noinline]] CellState LocusSolver::hiddenBelowFreeSpace(RowSample n, double hidden_t,
                                                              double& stop_t) const {
  if (!passesInFreeSpace(n)) return CellState::kUnknown;
  stop_t = hidden_t;
  return CellState::kShadow;
}

int LocusSolver::startRow(const Line& line, double z) const {
  const Eigen::Vector3d p = line.a + z * line.b;
  double row = rowOf(p.y(), p.z());
  // Rounded to the nearest row; truncation is a floor on positive numbers.
  row = std::clamp(std::isfinite(row) ? row : 0.0, -1.0, double(g_.rows));
  return std::clamp(int(row + 1.5) - 1, 0, g_.rows - 1);
}

// Scanline bracketing: from the start row, walk down the line while it is
// in front of the surface, or up while it is behind, until the sign of
// Delta changes between adjacent scanlines.
CellState LocusSolver::walk(const Line& line, int down, int row, Bracket& bracket,
                            CellResult& end) const {
  RowSample s = sampleRow(line, row);
  end.out_of_view = !s.at.on_image;
  if (!s.ok) {
    // Started where a ray met nothing: on from the first return below,
    // which, if the line is hidden there, walks up to that ray again.
    row = s.at.on_image ? firstReturnBelow(line, down, s) : -1;
    if (row < 0) return CellState::kUnknown;
    s = sampleRow(line, row);
  }
  const int step = s.delta < 0 ? down : -down;
  for (int next = row + step; next >= 0 && next < g_.rows; next += step) {
    const RowSample n = sampleRow(line, next);
    if (!n.ok)
      return n.at.on_image && s.delta > 0 ? hiddenBelowFreeSpace(n, s.at.t, end.z)
                                          : CellState::kUnknown;
    if ((n.delta < 0) != (s.delta < 0)) {
      bracket.upper = s.delta < 0 ? s : n;
      bracket.lower = s.delta < 0 ? n : s;
      return CellState::kKnown;
    }
    s = n;
  }
  // The line left the image without meeting the surface. Below the image it
  // is out of view. Above it, the line was hidden all the way. Nearer than
  // where the border scanline meets the ground, its ground would have been
  // in view, so something occludes it (a tall obstacle near the far edge);
  // beyond, nothing tells whether its ground is in the field of view.
  // Without ground at the border, the ground is taken at the image's
  // typical height, which would have been in view below the line's exit.
  if (s.delta < 0) return CellState::kUnknown;
  end.z = s.at.t;
  const int c = std::clamp(int(s.at.col + 0.5), 0, g_.cols - 1);
  const int b = s.row == 0 ? 0 : 1;
  const double border = tables_.borderReach(b)[std::size_t(c)];
  if (std::isnan(border))
    return s.at.t > tables_.typicalHeight() ? CellState::kShadow : CellState::kUnknown;
  const double reach = reachOf(line);
  if (!(reach < border)) return CellState::kUnknown;
  // Beyond the border pixels' own ground, up to where the next scanline
  // would meet it, which an obstacle's reach taken from beside them calls
  // hidden, the ground may as well go on in view: undecided. Between the two
  // columns around the line, whose ground the image interpolates.
  const int c0 = std::clamp(int(std::floor(s.at.col)), 0, g_.cols - 2);
  const auto& from = tables_.borderOwnFrom(b);
  const auto& to = tables_.borderOwnTo(b);
  end.undecided = reach >= std::min(from[std::size_t(c0)], from[std::size_t(c0) + 1]) &&
                  reach < std::max(to[std::size_t(c0)], to[std::size_t(c0) + 1]);
  return CellState::kShadow;
}

// Binary search on phi between the bracketing scanlines (krotkov1989
// §3.1), the image interpolated from the four surrounding pixels at each
// step. Within one scanline spacing the locus column theta_I(phi) is
// linear to far below a thousandth of a pixel, so it is interpolated
// between the exact columns at the two scanlines.
CellResult LocusSolver::refine(const Line& line, Bracket& br) const {
  const int sign = (br.lower.row - br.upper.row) * g_.phi_step > 0 ? 1 : -1;
  const double col_upper = br.upper.at.col, col_step = br.lower.at.col - br.upper.at.col;
  // The four pixels around the intersection: fixed for the whole search
  // unless the locus crosses a column boundary between the scanlines.
  int quad_col = std::clamp(int(std::min(col_upper, col_upper + col_step)), 0, g_.cols - 2);
  if (std::max(col_upper, col_upper + col_step) > quad_col + 1) quad_col = -1;
  std::array<double, 4> quad{};
  if (quad_col >= 0) {
    // A pixel without a return makes the search's f NaN: unknown.
    const double* upper = &range_[std::size_t(br.upper.row) * g_.cols + quad_col];
    const double* lower = &range_[std::size_t(br.lower.row) * g_.cols + quad_col];
    quad = {upper[0], upper[1], lower[0], lower[1]};
  }
  int used_quad_col = quad_col;
  auto imageRange = [&](double u_mid) {
    const double col = col_upper + u_mid * col_step;
    if (quad_col < 0) return rangeAt(br.upper.row, br.lower.row, u_mid, col, used_quad_col);
    const double fc = col - quad_col;
    const double top = quad[0] + fc * (quad[1] - quad[0]);
    return top + u_mid * (quad[2] + fc * (quad[3] - quad[2]) - top);
  };
  // With t = N / D, f = |a D + N b|^2 - I^2 D^2 = D^2 (rho_I^2 - I^2) has
  // the sign of Delta and its root, and needs neither a division nor a root.
  auto f = [&](double u_mid, double s, double c) {
    const double den = line.b.z() * c - line.b.y() * s;
    const double num = line.a.y() * s - line.a.z() * c;
    const double range = imageRange(u_mid);
    return (line.a * den + line.b * num).squaredNorm() - range * range * den * den;
  };
  auto fAtRow = [&](const RowSample& x) {
    const double den = 1.0 / inverse_den_[x.row];
    return den * den * x.delta * (2 * x.at.rho - x.delta);
  };
  // Bisection keeps u in front of the surface and u + 2h behind it.
  double u = 0.0, h = 0.5, f_lo = fAtRow(br.upper), f_hi = fAtRow(br.lower);
  double sin_lo = sin_phi_[br.upper.row], cos_lo = cos_phi_[br.upper.row];
  for (std::size_t level = 0; level < sin_half_.size(); ++level, h /= 2) {
    const double sh = sign * sin_half_[level], ch = cos_half_[level];
    const double s = sin_lo * ch + cos_lo * sh, c = cos_lo * ch - sin_lo * sh;
    const double f_mid = f(u + h, s, c);
    if (std::isnan(f_mid)) return {CellState::kUnknown};
    // Random either way, so written without a branch.
    const bool in_front = f_mid < 0;
    u = in_front ? u + h : u;
    f_lo = in_front ? f_mid : f_lo;
    f_hi = in_front ? f_hi : f_mid;
    sin_lo = in_front ? s : sin_lo;
    cos_lo = in_front ? c : cos_lo;
  }
  // Across the last bracket (2h wide) f is linear to far below the range
  // noise: its root by linear interpolation.
  double w = 2 * h * f_lo / (f_lo - f_hi);
  if (quad_col >= 0 && tables_.quadBends(std::min(br.upper.row, br.lower.row), quad_col)) {
    // The surface lies `shift` farther along the ray than the chord: f there
    // moves by -2 rho shift D^2, and the root with it along f's slope.
    const double shift = rowCurvatureShift(br, u + w, col_upper + (u + w) * col_step, quad_col);
    const double d = sign * w * std::abs(g_.phi_step);
    const double den = line.b.z() * (cos_lo - sin_lo * d) - line.b.y() * (sin_lo + cos_lo * d);
    w += 2 * imageRange(u + w) * shift * den * den * (2 * h) / (f_hi - f_lo);
    // The spline meets both scanlines' samples, so its root is between them.
    w = std::clamp(w, -u, 1 - u);
  }
  const double d = sign * w * std::abs(g_.phi_step), d2 = d * d;
  const double sd = d * (1 - d2 / 6), cd = 1 - d2 / 2 + d2 * d2 / 24;  // |d| <= one scanline step
  const double s = sin_lo * cd + cos_lo * sd, c = cos_lo * cd - sin_lo * sd;
  const double t = (line.a.y() * s - line.a.z() * c) / (line.b.z() * c - line.b.y() * s);
  CellResult result = finish(line, br, t, u + w, col_upper + (u + w) * col_step, used_quad_col);
  result.row = br.upper.row + (u + w) * (br.lower.row - br.upper.row);
  return result;
}

// How much farther along the ray than the bilinear range at u (between the
// bracket's scanlines, at column col) the Catmull-Rom spline through the
// scanlines either side puts the surface: ground that bends between
// scanlines meeting it tens of centimetres apart (rowCurvature(): second
// differences beyond their noise).
double LocusSolver::rowCurvatureShift(const Bracket& br, double u, double col, int quad_col) const {
  const double fc = col - quad_col;
  const double* upper = &row_curvature_[std::size_t(br.upper.row) * g_.cols + quad_col];
  const double* lower = &row_curvature_[std::size_t(br.lower.row) * g_.cols + quad_col];
  const double d_upper = upper[0] + fc * (upper[1] - upper[0]);
  const double d_lower = lower[0] + fc * (lower[1] - lower[0]);
  // One bend alone, or two of opposite signs, is a kink or an inflection,
  // over which the spline overshoots: there the chord stands.
  if (!(d_upper * d_lower > 0)) return 0.0;
  return 0.5 * u * (u - 1) * ((1 - u) * d_upper + u * d_lower);
}

// Shadow, face, oblique or known; for a cell with a height, its sigma.
CellResult LocusSolver::finish(const Line& line, Bracket& br, double t, double u, double col,
                               int quad_col) const {
  const int quad_row = std::min(br.upper.row, br.lower.row);
  if (edges_.quadIsEdge(quad_row, quad_col)) {
    CellResult shadow{CellState::kShadow, t};
    shadow.undecided =
        (undecided_steps_ > 0 || far_end_share_ > 0) && isUndecided(line, quad_row, col);
    return shadow;
  }
  if (tables_.isSteepFace(quad_row, quad_col) || tables_.isSparse(quad_row, quad_col))
    return {CellState::kUnknown};
  const HeightNoise noise = sigmaOfHeight(line, br, u, col, quad_col);
  const double sampling = tables_.samplingSigma(quad_row, quad_col);
  const double* q = range_ + std::size_t(quad_row) * g_.cols + quad_col;
  const bool noise_may_hide_gap =
      std::max(std::max(q[0], q[1]), std::max(q[g_.cols], q[g_.cols + 1])) > max_sure_range_;
  const auto state = edges_.quadIsGrazing(quad_row, quad_col) || noise_may_hide_gap
                         ? CellState::kOblique
                         : CellState::kKnown;
  return {state, t, std::sqrt(noise.sigma * noise.sigma + sampling * sampling), noise};
}

// The jump across a quad at one image column: its near and far scanlines
// (by horizontal reach from the sensor), and the samples' horizontal step
// before it. Invalid where the quad is no jump larger than two such steps.
struct LocusSolver::Jump {
  int column = 0, near = 0, dir = 1;  // far = near + dir
  double near_reach = NAN, step = NAN;
  bool valid() const { return std::isfinite(step); }
};

LocusSolver::Jump LocusSolver::jumpAt(int quad_row, double col) const {
  Jump j;
  j.column = std::clamp(int(std::lround(col)), 0, g_.cols - 1);
  const double upper = reachAt(quad_row, j.column), lower = reachAt(quad_row + 1, j.column);
  j.dir = upper < lower ? 1 : -1;
  j.near = upper < lower ? quad_row : quad_row + 1;
  const int before = j.near - 2 * j.dir;
  if (before < 0 || before >= g_.rows) return j;
  j.near_reach = reachAt(j.near, j.column);
  const double noise = sensor::rangeSigma(image_.at(j.near, j.column), image_.range_sigma_k);
  const double step = (j.near_reach - reachAt(before, j.column)) / 2 - 1.5 * std::sqrt(2.0) * noise;
  // NaN (a pixel without a return) fails every test.
  if (step > 0 && std::max(upper, lower) - j.near_reach > 2 * step) j.step = step;
  return j;
}

// krotkov1989 §3.2: an occluding edge lies somewhere between the last
// sample on the occluder and where the next would have met it had it gone
// on: one step of the samples before, horizontally. Ground up to there may
// have been seen at the last samples' grazing angle, or hidden; a smooth
// crest hides nothing until it turns away from the ray. Only for a jump
// across scanlines at the cell's column, larger than two such steps; the
// step is the mean over two scanlines, less 1.5 std. dev. of the range
// difference it comes from.
bool LocusSolver::isUndecided(const Line& line, int quad_row, double col) const {
  const Jump jump = jumpAt(quad_row, col);
  if (!jump.valid()) return false;
  const double cell_reach = reachOf(line);
  // Each rule only where it is on: the near one's test, at 0 steps, would
  // still take cells nearer than the last sample.
  if (undecided_steps_ > 0 && cell_reach - jump.near_reach < undecided_steps_ * jump.step)
    return true;
  return far_end_share_ > 0 && cell_reach > shadowFarEndFrom(jump);
}

// Behind a crest the last ray over it, tangent somewhere past the last
// sample, meets the ground beyond between two bounds: where the ray through
// the last sample meets that ground extended back (a line through its first
// two samples, in the vertical plane of the column), and the ground's first
// sample. Ground in the far share of that stretch may have been seen.
// Behind a face the occluder may go on past its last sample and the shadow
// with it: no bound there (+inf).
double LocusSolver::shadowFarEndFrom(const Jump& jump) const {
  const int prev = jump.near - jump.dir, far = jump.near + jump.dir, far2 = far + jump.dir;
  if (far2 < 0 || far2 >= g_.rows || prev < 0 || prev >= g_.rows) return INFINITY;
  auto at = [&](int r) {
    return Eigen::Vector2d(
        reachAt(r, jump.column),
        tables_.world()[std::size_t(r) * g_.cols + jump.column].z() - origin_.z());
  };
  const Eigen::Vector2d last = at(jump.near), segment = last - at(prev);
  // NaN fails the test: no bound.
  if (!(std::abs(segment.dot(last)) > cos_crest_ * segment.norm() * last.norm())) return INFINITY;
  const Eigen::Vector2d first = at(far), ground = at(far2) - first;
  // The ray s * last meets first + u * ground: s (last x ground) = first x ground.
  const double cross = last.x() * ground.y() - last.y() * ground.x();
  const double s = (first.x() * ground.y() - first.y() * ground.x()) / cross;
  const double ray_end = std::clamp(s * last.x(), last.x(), first.x());
  if (!std::isfinite(ray_end)) return INFINITY;
  return first.x() - far_end_share_ * (first.x() - ray_end);
}

// Bilinear (four-point Lagrange) interpolation of the image between two
// adjacent scanlines at fraction u from `upper` and fractional column
// `col`; NaN when one of the four pixels has no return.
double LocusSolver::rangeAt(int upper, int lower, double u, double col, int& quad_col) const {
  // Columns on the image are > -0.5, where truncation and floor agree after
  // the clamp (and truncation is not a library call).
  quad_col = std::clamp(int(col), 0, g_.cols - 2);
  const double fc = col - quad_col;  // beyond [0, 1] within half a pixel of the border
  const double* a = &range_[std::size_t(upper) * g_.cols + quad_col];
  const double* b = &range_[std::size_t(lower) * g_.cols + quad_col];
  const double top = a[0] + fc * (a[1] - a[0]);
  return top + u * (b[0] + fc * (b[1] - b[0]) - top);
}

// Std. dev. of rangeAt() from the pixels' noise, sigma_rho = k rho^2 each.
double LocusSolver::noiseOfRange(int upper, int lower, double u, double col) const {
  const int c0 = std::clamp(int(col), 0, g_.cols - 2);
  const double fc = std::clamp(col - c0, 0.0, 1.0);
  const std::array<double, 4> w{(1 - u) * (1 - fc), (1 - u) * fc, u * (1 - fc), u * fc};
  const std::array<double, 4> rho{image_.at(upper, c0), image_.at(upper, c0 + 1),
                                  image_.at(lower, c0), image_.at(lower, c0 + 1)};
  double variance = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double s = sensor::rangeSigma(rho[i], image_.range_sigma_k);
    variance += w[i] * w[i] * s * s;
  }
  return std::sqrt(variance);
}

// The image range along one scanline, interpolated between columns; NaN
// without returns.
double LocusSolver::imageRangeOnRow(int row, double col) const {
  const int c0 = std::clamp(int(col), 0, g_.cols - 2);
  const double* a = &range_[std::size_t(row) * g_.cols + c0];
  return a[0] + (col - c0) * (a[1] - a[0]);
}

// Linearised propagation (docs/elevation-uncertainty.md): an error e in the
// interpolated range moves the root of Delta by e / (dDelta/drow) and the
// height by (dt/drow) times that. e has two parts: the pixels' noise
// through the interpolation weights, and the interpolation error, bounded
// by 1/8 of the image's second difference along the locus. dDelta/drow is
// a least-squares slope over up to four scanlines, which damps the noise of
// a two-point difference; an outer scanline across an occluding edge is
// left out of the slope. The outer scanlines' samples go into the bracket
// (above, below), where followBand() goes on from them, and not into the
// result, which is copied on its way back up.
HeightNoise LocusSolver::sigmaOfHeight(const Line& line, Bracket& br, double u, double col,
                                       int quad_col) const {
  const int step = br.lower.row - br.upper.row;
  HeightNoise result;
  // The locus column is linear in the row to below a thousandth of a pixel
  // over three scanlines (at most 7e-4 pixel in the course's scans): one
  // step on from the bracket's.
  const double col_step = br.lower.at.col - br.upper.at.col;
  if (br.upper.row - step >= 0 && br.upper.row - step < g_.rows)
    br.above = sampleRowAt(line, br.upper.row - step, br.upper.at.col - col_step);
  if (br.lower.row + step >= 0 && br.lower.row + step < g_.rows)
    br.below = sampleRowAt(line, br.lower.row + step, br.lower.at.col + col_step);
  const std::array<const RowSample*, 4> samples{&br.above, &br.upper, &br.lower, &br.below};
  std::array<bool, 4> ok{};
  std::array<double, 4> delta{}, range{};
  for (int i = 0; i < 4; ++i) {
    ok[i] = samples[i]->ok;
    delta[i] = samples[i]->delta, range[i] = samples[i]->at.rho - samples[i]->delta;
  }
  if (!ok[1] || !ok[2]) return result;
  if (ok[0] && edges_.quadIsEdge(std::min(br.upper.row, br.upper.row - step), quad_col))
    ok[0] = false;
  if (ok[3] && edges_.quadIsEdge(std::min(br.lower.row, br.lower.row + step), quad_col))
    ok[3] = false;
  double sum_k = 0, sum_kk = 0, sum_d = 0, sum_kd = 0;
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    if (!ok[i]) continue;
    const double k = i - 1;
    sum_k += k, sum_kk += k * k, sum_d += delta[i], sum_kd += k * delta[i], ++n;
  }
  const double spread_k = n * sum_kk - sum_k * sum_k;
  const double slope = (n * sum_kd - sum_k * sum_d) / spread_k;
  if (slope == 0.0) return result;
  // Standard error of the slope from the pixels' noise alone.
  const double noise = sensor::rangeSigma(br.upper.at.rho, image_.range_sigma_k);
  const bool insignificant = std::abs(slope) < 3 * noise * std::sqrt(n / spread_k);
  const bool band_continues = (ok[0] && delta[0] > -3 * noise) || (ok[3] && delta[3] < 3 * noise);
  double curvature = 0.0;
  if (ok[0]) curvature = std::abs(range[0] - 2 * range[1] + range[2]);
  if (ok[3]) curvature = std::max(curvature, std::abs(range[1] - 2 * range[2] + range[3]));
  // Less the pixels' noise, which the noise term counts already: a second
  // difference's noise variance is 6 pixel variances.
  const double curvature_variance = std::max(curvature * curvature - 6 * noise * noise, 0.0);
  const double noise_sigma = noiseOfRange(br.upper.row, br.lower.row, u, col);
  const double range_sigma = std::sqrt(noise_sigma * noise_sigma + curvature_variance / 64);
  result.height_per_range = std::abs((br.lower.at.t - br.upper.at.t) / slope);
  result.sigma = result.height_per_range * range_sigma;
  result.significant = !insignificant;
  result.ambiguous = insignificant || band_continues;
  return result;
}

// Follows the line up and down from the bracket over the scanlines where
// |Delta| is within 3 sigma of the range noise, the stretch that may hold
// the surface.
Band LocusSolver::followBand(const Line& line, int down, const Bracket& br) const {
  const double noise_per_rho2 = 3 * image_.range_sigma_k;
  // From one end of the bracket, `away` from the other, while Delta has
  // not left the noise on the side away from the bracket. The first step
  // is the neighbour sigmaOfHeight() sampled.
  auto follow = [&](const RowSample& end, const RowSample& neighbour, int step, double away) {
    Band part;
    double delta = end.delta, rho = end.at.rho, t = end.at.t;
    for (int row = end.row + step;; row += step) {
      const double noise = noise_per_rho2 * rho * rho;
      if (std::abs(delta) < noise) part.add(row - step, t, delta);
      if (!(away * delta < noise) || row < 0 || row >= g_.rows) return part;
      const RowSample next = row == end.row + step ? neighbour : sampleRow(line, row);
      if (!next.ok) return part;
      delta = next.delta, rho = next.at.rho, t = next.at.t;
    }
  };
  Band band = follow(br.lower, br.below, down, 1.0);
  band.merge(follow(br.upper, br.above, -down, -1.0));
  return band;
}

// The first cell from `c` on whose search starts on the image. Across a
// map row the field of view is one interval, so the cells out of it are
// skipped in strides of up to 16 (80 cm at 5 cm) and the edge found by
// bisection: about half the map is out of view, and a cell there cost as
// much as its first sample (they stay unknown, as a new map's cells are).
int nextInView(const LocusSolver& solver, const GridSpec& grid, int r, int c, double z_guess) {
  auto inView = [&](int col) {
    const auto p = grid.cellCenter(r, col);
    return solver.startsInView(p.x(), p.y(), z_guess);
  };
  int out = c - 1;  // the last cell known to be out of view
  for (int stride = 1; out + stride < grid.cols; stride = std::min(2 * stride, 16)) {
    if (!inView(out + stride)) {
      out += stride;
      continue;
    }
    int in = out + stride;
    while (in - out > 1) {
      const int mid = out + (in - out) / 2;
      (inView(mid) ? in : out) = mid;
    }
    return in;
  }
  return grid.cols;
}

// lround(step * a / |(a, b)|), compared in squares: this runs for every
// shadow cell, and the root and the rounding calls were a measurable share.
int roundedStep(double a, double b, int step) {
  const double a2 = a * a, n2 = a2 + b * b, s2 = double(step * step) * a2;
  int m = 0;
  while (m < step && s2 >= (m + 0.5) * (m + 0.5) * n2) ++m;
  return a < 0 ? -m : m;
}

// The neighbour (rows, columns) one step across a line of sight `along`
// (the direction (-y, x)), rounded to a neighbour: shadows' sides and faces'
// sides are taken across it.
std::pair<int, int> stepAcross(const Eigen::Vector2d& along) {
  return {roundedStep(along.x(), along.y(), 1), -roundedStep(along.y(), along.x(), 1)};
}

// A shadow's sides, where the occluder's silhouette ends and its range jump
// fades below the edge test, are where interpolated heights meet unseen
// ground: a known cell whose neighbour across the line of sight from
// `sensor` (either side) is shadow becomes oblique, its height kept. With
// `far_ends`, so do the known cells one and two steps beyond a shadow along
// the line of sight: a hidden floor's far end, which interpolation gives
// the height of the far wall's face.
void markShadowSidesOblique(ElevationMap& map, const Eigen::Vector2d& sensor, bool far_ends) {
  const GridSpec& g = map.grid();
  // Read as it changes: only known cells change, and only to oblique.
  const Layer& state = map.layer(layer::kState);
  auto makeOblique = [&](int r, int c) {
    if (g.hasCell(r, c) && state(r, c) == float(CellState::kKnown))
      map.setHeight(r, c, CellState::kOblique, map.elevation(r, c), map.sigma(r, c),
                    map.count(r, c));
  };
  // From each shadow cell to its known neighbours: far fewer than the
  // known cells, most of which have no shadow near.
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      if (state(r, c) != float(CellState::kShadow)) continue;
      const Eigen::Vector2d along = g.cellCenter(r, c) - sensor;
      const auto [dr, dc] = stepAcross(along);
      makeOblique(r + dr, c + dc);
      makeOblique(r - dr, c - dc);
      if (!far_ends) continue;
      for (const int step : {1, 2})
        makeOblique(r + roundedStep(along.y(), along.x(), step),
                    c + roundedStep(along.x(), along.y(), step));
    }
}

}  // namespace

void widenSigmaBesideFaces(ElevationMap& map, const std::vector<float>& face_noise,
                           const Eigen::Vector2d& sensor, double noise_sigmas) {
  if (!(noise_sigmas > 0)) return;
  const GridSpec& g = map.grid();
  if (face_noise.size() != std::size_t(g.rows) * g.cols)
    throw std::invalid_argument("widenSigmaBesideFaces: face_noise is not the size of the map");
  // Decided on the sigmas as the solver left them, then applied: a cell
  // may be beside two faces, and a face cell beside another.
  std::vector<std::pair<std::size_t, double>> spreads;
  const float* faces = face_noise.data();
  for (std::size_t i = 0; i < face_noise.size(); ++i) {
    if (std::isnan(faces[i])) continue;  // nearly every cell: kept to one test
    const int r = int(i / std::size_t(g.cols)), c = int(i % std::size_t(g.cols));
    const double noise = faces[i];
    if (!map.hasHeight(r, c)) continue;
    const auto [dr, dc] = stepAcross(g.cellCenter(r, c) - sensor);
    for (const int side : {1, -1}) {
      const int nr = r + side * dr, nc = c + side * dc;
      if (!g.hasCell(nr, nc) || !map.hasHeight(nr, nc)) continue;
      // A face rises from the neighbour's height (or falls to it): the
      // band's middle lies beyond the noise of both. Far ground under
      // heavy noise makes bands about the ground's height too, no face.
      const double offset = std::abs(double(map.elevation(r, c)) - map.elevation(nr, nc));
      const double s = map.sigma(nr, nc);
      if (offset * offset > noise_sigmas * noise_sigmas * (s * s + noise * noise))
        spreads.emplace_back(std::size_t(nr) * g.cols + nc,
                             offset + std::sqrt(3.0) * map.sigma(r, c));
    }
  }
  // The largest spread of each cell last.
  std::sort(spreads.begin(), spreads.end());
  for (std::size_t k = 0; k < spreads.size(); ++k) {
    const auto [i, w] = spreads[k];
    if (k + 1 < spreads.size() && spreads[k + 1].first == i) continue;
    const int r = int(i / std::size_t(g.cols)), c = int(i % std::size_t(g.cols));
    const double s = map.sigma(r, c);
    map.setHeight(r, c, map.state(r, c), map.elevation(r, c), std::sqrt(s * s + w * w / 12),
                  map.count(r, c));
  }
}

double rangeWhereNoiseMayHideGap(double k, const LocusOptions& options) {
  if (!(k > 0)) return INFINITY;
  return std::sqrt(options.max_gap_hidden_by_noise_m /
                   (options.edges.noise_sigmas * std::sqrt(2.0) * k));
}

ElevationMap buildLocusMap(const RangeImage& image, const GridSpec& grid,
                           const LocusOptions& options) {
  ElevationMap map(grid, "world");
  if (image.rows() < 2 || image.cols() < 2) return map;
  const OccludingEdges edges(image, options.edges);
  const double epsilon =
      options.epsilon_rad > 0 ? options.epsilon_rad : std::abs(image.geometry.phi_step) / 4;
  const LocusSolver solver(image, edges, epsilon, options);
  std::vector<std::uint8_t> undecided(std::size_t(grid.rows) * grid.cols, 0);
  std::vector<float> face_noise(undecided.size(), NAN);
  const double start_z = solver.typicalHeight();
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();

#pragma omp parallel for schedule(dynamic, 8) num_threads(threads)
  for (int r = 0; r < grid.rows; ++r) {
    double z_guess = start_z;  // neighbouring cells have similar heights
    double row_hint = NAN;
    for (int c = 0; c < grid.cols;) {
      const auto p = grid.cellCenter(r, c);
      const auto result = solver.solve(p.x(), p.y(), z_guess, row_hint);
      row_hint = result.row;
      undecided[std::size_t(r) * grid.cols + c] = result.undecided;
      if (!std::isnan(result.face_noise))
        face_noise[std::size_t(r) * grid.cols + c] = float(result.face_noise);
      if (hasHeight(result.state))
        map.setHeight(r, c, result.state, result.z, result.sigma);
      else
        map.setUnobserved(r, c, result.state);
      if (result.state != CellState::kUnknown) z_guess = result.z;
      c = result.out_of_view ? nextInView(solver, grid, r, c + 1, z_guess) : c + 1;
    }
  }
  if (options.oblique_shadow_sides)
    markShadowSidesOblique(map, image.sensor_to_world.translation().head<2>(),
                           options.oblique_shadow_far_ends);
  // After the sides: they border the whole stretch a shadow's edge may lie in.
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (undecided[std::size_t(r) * grid.cols + c]) map.setUnobserved(r, c, CellState::kUnknown);
  widenSigmaBesideFaces(map, face_noise, image.sensor_to_world.translation().head<2>(),
                        options.face_side_noise_sigmas);
  return map;
}

}  // namespace ambler::terrain

#include "footfall/Footprint.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::footfall {

namespace {

// A padded copy of the map around the candidates, R cells beyond them on
// every side so that each footprint lies inside it. Cells outside the map
// are not known.
struct Window {
  int rows = 0, cols = 0;
  std::vector<unsigned char> known;
  // Known, and so is every cell within the clearance of it: where a sole
  // may rest.
  std::vector<unsigned char> clear;
  std::vector<double> z, sigma;  // z relative to the reference; 0 unless known
  int index(int r, int c) const { return r * cols + c; }
};

// Cells nobody saw (shadow, unknown or oblique) come in scattered specks
// under range noise, and a hidden strip behind a pebble is often one cell
// next to such a speck: a sole clear of them by `clearance` cells rests on
// ground that was seen.
bool clearOfUnseen(const terrain::ElevationMap& map, int row, int col, int clearance) {
  const GridSpec& g = map.grid();
  for (int r = row - clearance; r <= row + clearance; ++r)
    for (int c = col - clearance; c <= col + clearance; ++c)
      if (!g.hasCell(r, c) || !map.isKnown(r, c)) return false;
  return true;
}

Window extractWindow(const terrain::ElevationMap& map, const CandidateCells& cells, int radius,
                     int clearance, double& reference_z) {
  Window w;
  w.rows = cells.grid.rows + 2 * radius;
  w.cols = cells.grid.cols + 2 * radius;
  const std::size_t n = std::size_t(w.rows) * w.cols;
  w.known.assign(n, 0);
  w.clear.assign(n, 0);
  w.z.assign(n, 0.0);
  w.sigma.assign(n, 0.0);
  const GridSpec& g = map.grid();
  double sum = 0.0;
  int count = 0;
  for (int r = 0; r < w.rows; ++r)
    for (int c = 0; c < w.cols; ++c) {
      const int mr = cells.first_row - radius + r, mc = cells.first_col - radius + c;
      if (!g.hasCell(mr, mc) || !map.isKnown(mr, mc)) continue;
      const int i = w.index(r, c);
      w.known[i] = 1;
      w.clear[i] = clearance == 0 || clearOfUnseen(map, mr, mc, clearance);
      w.z[i] = map.elevation(mr, mc);
      w.sigma[i] = map.sigma(mr, mc);
      sum += w.z[i], ++count;
    }
  // Heights relative to their mean keep the sums of squares well conditioned.
  reference_z = count > 0 ? sum / count : 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (w.known[i]) w.z[i] -= reference_z;
  return w;
}

// Prefix sums along each window row: the sum over columns c0..c1 of a row
// is two lookups.
class RowPrefix {
 public:
  template <typename Value>  // double(int index, int col)
  RowPrefix(const Window& w, Value value)
      : stride_(w.cols + 1), sums_(std::size_t(w.rows) * stride_, 0.0) {
    for (int r = 0; r < w.rows; ++r)
      for (int c = 0; c < w.cols; ++c)
        sums_[r * stride_ + c + 1] = sums_[r * stride_ + c] + value(w.index(r, c), c);
  }
  double span(int row, int c0, int c1) const {
    return sums_[row * stride_ + c1 + 1] - sums_[row * stride_ + c0];
  }

 private:
  int stride_;
  std::vector<double> sums_;
};

// For each half-width w = 0..R, the extreme of one window row over columns
// c - w..c + w, built from that of w - 1 in one pass (the spans at c - 1, c
// and c + 1 cover c - w..c + w). A ring of 2R + 1 of them holds the rows
// under the feet of one row of candidates.
template <typename Pick>
class RowExtremesRing {
 public:
  RowExtremesRing(const Window& w, const std::vector<double>& values, int radius, Pick pick)
      : w_(w),
        values_(values),
        radius_(radius),
        pick_(pick),
        levels_(std::size_t(2 * radius + 1) * (radius + 1) * w.cols, 0.0) {}

  // Makes window rows first..first + 2R available.
  void prepare(int first) {
    for (int row = std::max(first, next_row_); row <= first + 2 * radius_; ++row) compute(row);
    next_row_ = first + 2 * radius_ + 1;
  }
  double at(int row, int half, int col) const { return level(row, half)[col]; }

 private:
  double* level(int row, int half) {
    return &levels_[(std::size_t(row % (2 * radius_ + 1)) * (radius_ + 1) + half) * w_.cols];
  }
  const double* level(int row, int half) const {
    return &levels_[(std::size_t(row % (2 * radius_ + 1)) * (radius_ + 1) + half) * w_.cols];
  }
  void compute(int row) {
    std::copy_n(&values_[w_.index(row, 0)], w_.cols, level(row, 0));
    for (int half = 1; half <= radius_; ++half) {
      const double* prev = level(row, half - 1);
      double* next = level(row, half);
      for (int c = half; c + half < w_.cols; ++c)
        next[c] = pick_(prev[c], pick_(prev[c - 1], prev[c + 1]));
    }
  }

  const Window& w_;
  const std::vector<double>& values_;
  int radius_;
  Pick pick_;
  std::vector<double> levels_;
  int next_row_ = 0;
};

// A histogram of quantised heights with a coarse level of 64 bins per block,
// so that the k-th highest value is found in a few dozen steps while the foot
// slides along a row of candidates (Huang's running median, generalised).
class HeightHistogram {
 public:
  HeightHistogram(double lowest, double highest, double bin)
      : lowest_(lowest), bin_(bin), fine_(std::size_t((highest - lowest) / bin) + 2, 0) {
    coarse_.assign(fine_.size() / kBlock + 1, 0);
  }
  int binOf(double z) const {
    return std::clamp(int((z - lowest_) / bin_), 0, int(fine_.size()) - 1);
  }
  void add(double z, int delta) {
    const int b = binOf(z);
    fine_[b] += delta;
    coarse_[b / kBlock] += delta;
  }
  void clear() {
    std::fill(fine_.begin(), fine_.end(), 0);
    std::fill(coarse_.begin(), coarse_.end(), 0);
  }
  // Upper edge of the bin holding the k-th highest value, searching down
  // from the bin of `at_most` (no value is higher).
  double kthHighest(int k, double at_most) const {
    int block = binOf(at_most) / kBlock, seen = 0;
    for (; block > 0 && seen + coarse_[block] < k; --block) seen += coarse_[block];
    int b = std::min(block * kBlock + kBlock - 1, int(fine_.size()) - 1);
    for (; b > 0 && seen + fine_[b] < k; --b) seen += fine_[b];
    return lowest_ + (b + 1) * bin_;
  }

 private:
  static constexpr int kBlock = 64;
  double lowest_, bin_;
  std::vector<int> fine_, coarse_;
};

void computeKthHighest(const Window& w, const std::vector<double>& lo, double fraction, double bin,
                       FootprintStatistics& s) {
  const int radius = s.disk.radius_cells;
  const int k =
      std::clamp(int(std::ceil(fraction * s.disk.cell_count - 1e-9)), 1, s.disk.cell_count);
  double lowest = INFINITY, highest = -INFINITY;
  for (std::size_t i = 0; i < lo.size(); ++i)
    if (w.known[i]) lowest = std::min(lowest, lo[i]), highest = std::max(highest, lo[i]);
  if (!(highest >= lowest)) return;
  // At most 4 million bins, whatever the relief.
  HeightHistogram histogram(lowest, highest, std::max(bin, (highest - lowest) / 4e6));
  const GridSpec& g = s.cells.grid;
  for (int r = 0; r < g.rows; ++r) {
    histogram.clear();
    const int wr = r + radius;
    for (int dy = -radius; dy <= radius; ++dy) {
      const int half = s.disk.half_width[dy + radius];
      for (int c = radius - half; c <= radius + half; ++c) {
        const int i = w.index(wr + dy, c);
        if (w.known[i]) histogram.add(lo[i], 1);
      }
    }
    for (int c = 0; c < g.cols; ++c) {
      const int i = g.index(r, c);
      if (s.valid[i]) s.kth_highest_lo[i] = histogram.kthHighest(k, s.top[i]);
      if (c + 1 == g.cols) break;
      // Slide one column right: per footprint row, drop its leftmost cell
      // and take the one beyond its right end.
      const int wc = c + radius;
      for (int dy = -radius; dy <= radius; ++dy) {
        const int half = s.disk.half_width[dy + radius];
        const int out = w.index(wr + dy, wc - half), in = w.index(wr + dy, wc + half + 1);
        if (w.known[out]) histogram.add(lo[out], -1);
        if (w.known[in]) histogram.add(lo[in], 1);
      }
    }
  }
}

}  // namespace

DiskFootprint DiskFootprint::forDiameter(double diameter_m, double resolution_m) {
  if (!(diameter_m > 0 && std::isfinite(diameter_m)))
    throw std::invalid_argument("foot diameter must be a positive number of metres");
  if (!(resolution_m > 0 && std::isfinite(resolution_m)))
    throw std::invalid_argument("map resolution must be a positive number of metres");
  const double r = diameter_m / 2 / resolution_m;  // [cells]
  if (r > 500) throw std::invalid_argument("foot spans more than 1000 map cells");
  DiskFootprint d;
  d.radius_cells = int(std::floor(r));
  for (int dy = -d.radius_cells; dy <= d.radius_cells; ++dy) {
    const int half = int(std::floor(std::sqrt(std::max(r * r - dy * dy, 0.0))));
    d.half_width.push_back(half);
    d.cell_count += 2 * half + 1;
    for (int dx = -half; dx <= half; ++dx) d.sum_dx2 += dx * dx;
  }
  return d;
}

namespace {

// The map's cells whose centres lie in a finite region, clipped to the map:
// columns c0..c1, rows r0..r1 (none when c1 < c0 or r1 < r0).
struct CentreSpan {
  int c0, c1, r0, r1;
  bool empty() const { return c1 < c0 || r1 < r0; }
};

CentreSpan centresIn(const GridSpec& map_grid, const Box2& region) {
  const double res = map_grid.resolution;
  return {
      std::max(0, int(std::ceil((region.x_min - map_grid.origin_x) / res - 0.5))),
      std::min(map_grid.cols - 1, int(std::floor((region.x_max - map_grid.origin_x) / res - 0.5))),
      std::max(0, int(std::ceil((region.y_min - map_grid.origin_y) / res - 0.5))),
      std::min(map_grid.rows - 1, int(std::floor((region.y_max - map_grid.origin_y) / res - 0.5)))};
}

bool isFiniteBox(const Box2& region) {
  return std::isfinite(region.x_min) && std::isfinite(region.x_max) &&
         std::isfinite(region.y_min) && std::isfinite(region.y_max) &&
         region.x_min <= region.x_max && region.y_min <= region.y_max;
}

}  // namespace

bool holdsCellCentre(const GridSpec& map_grid, const Box2& region) {
  return isFiniteBox(region) && !centresIn(map_grid, region).empty();
}

CandidateCells candidateCells(const GridSpec& map_grid, const Box2& region) {
  if (!isFiniteBox(region))
    throw std::invalid_argument("footfall region must be a finite box with min <= max");
  const double res = map_grid.resolution;
  const CentreSpan span = centresIn(map_grid, region);
  if (span.empty()) throw std::invalid_argument("footfall region holds no cell centre of the map");
  CandidateCells cells;
  cells.first_row = span.r0;
  cells.first_col = span.c0;
  cells.grid.origin_x = map_grid.origin_x + span.c0 * res;
  cells.grid.origin_y = map_grid.origin_y + span.r0 * res;
  cells.grid.resolution = res;
  cells.grid.rows = span.r1 - span.r0 + 1;
  cells.grid.cols = span.c1 - span.c0 + 1;
  return cells;
}

FootprintStatistics computeFootprintStatistics(const terrain::ElevationMap& map, const Box2& region,
                                               const StatisticsRequest& request) {
  if (!(request.sigma_margin >= 0 && std::isfinite(request.sigma_margin)))
    throw std::invalid_argument("sigma margin must be a finite number >= 0");
  FootprintStatistics s;
  s.cells = candidateCells(map.grid(), region);
  s.disk = DiskFootprint::forDiameter(request.diameter_m, map.grid().resolution);
  const int radius = s.disk.radius_cells;
  const Window w = extractWindow(map, s.cells, radius, request.clearance_cells, s.reference_z);

  const double k = request.sigma_margin;
  std::vector<double> hi(w.z.size()), lo(w.z.size());
  for (std::size_t i = 0; i < w.z.size(); ++i)
    hi[i] = w.z[i] + k * w.sigma[i], lo[i] = w.z[i] - k * w.sigma[i];
  const RowPrefix unknown(w, [&](int i, int) { return w.clear[i] ? 0.0 : 1.0; });
  const RowPrefix z(w, [&](int i, int) { return w.z[i]; });
  const RowPrefix z2(w, [&](int i, int) { return w.z[i] * w.z[i]; });
  const RowPrefix cz(w, [&](int i, int c) { return c * w.z[i]; });
  const RowPrefix zlo(w, [&](int i, int) { return lo[i]; });
  const RowPrefix clo(w, [&](int i, int c) { return c * lo[i]; });
  const RowPrefix var(w, [&](int i, int) { return w.sigma[i] * w.sigma[i]; });
  auto max = [](double a, double b) { return std::max(a, b); };
  auto min = [](double a, double b) { return std::min(a, b); };
  RowExtremesRing highest(w, hi, radius, max);
  RowExtremesRing lowest(w, lo, radius, min);

  const GridSpec& g = s.cells.grid;
  const std::size_t n = std::size_t(g.cellCount());
  s.valid.assign(n, 0);
  for (auto* v : {&s.top, &s.bottom, &s.sum_z, &s.sum_z2, &s.sum_xz, &s.sum_yz, &s.sum_lo,
                  &s.sum_xlo, &s.sum_ylo, &s.sum_var})
    v->assign(n, NAN);
  for (int r = 0; r < g.rows; ++r) {
    highest.prepare(r);
    lowest.prepare(r);
    for (int c = 0; c < g.cols; ++c) {
      const int wr = r + radius, wc = c + radius, i = g.index(r, c);
      double bad = 0, top = -INFINITY, bottom = INFINITY;
      double sz = 0, sz2 = 0, scz = 0, syz = 0, slo = 0, sclo = 0, sylo = 0, svar = 0;
      for (int dy = -radius; dy <= radius; ++dy) {
        const int half = s.disk.half_width[dy + radius], row = wr + dy;
        const int c0 = wc - half, c1 = wc + half;
        bad += unknown.span(row, c0, c1);
        top = std::max(top, highest.at(row, half, wc));
        bottom = std::min(bottom, lowest.at(row, half, wc));
        const double row_z = z.span(row, c0, c1), row_lo = zlo.span(row, c0, c1);
        sz += row_z, sz2 += z2.span(row, c0, c1), scz += cz.span(row, c0, c1), syz += dy * row_z;
        slo += row_lo, sclo += clo.span(row, c0, c1), sylo += dy * row_lo;
        svar += var.span(row, c0, c1);
      }
      if (bad > 0.5) continue;
      s.valid[i] = 1;
      s.top[i] = top, s.bottom[i] = bottom;
      s.sum_z[i] = sz, s.sum_z2[i] = sz2, s.sum_xz[i] = scz - wc * sz, s.sum_yz[i] = syz;
      s.sum_lo[i] = slo, s.sum_xlo[i] = sclo - wc * slo, s.sum_ylo[i] = sylo;
      s.sum_var[i] = svar;
    }
  }
  if (request.support_fraction > 0) {
    s.kth_highest_lo.assign(n, NAN);
    computeKthHighest(w, lo, request.support_fraction, request.support_bin_m, s);
  }
  return s;
}

}  // namespace ambler::footfall

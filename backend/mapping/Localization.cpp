#include "mapping/Localization.h"
#include <chrono>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace ambler::mapping {

namespace {

// The model's heights at the nodes (x0 + i cell, y0 + j cell); NaN where it
// has none.
struct Lattice {
  double cell = 1.0, x0 = 0.0, y0 = 0.0;
  int cols = 0, rows = 0;
  std::vector<double> z;

  double node(int i, int j) const {
    if (i < 0 || j < 0 || i >= cols || j >= rows) return NAN;
    return z[std::size_t(j) * std::size_t(cols) + std::size_t(i)];
  }
};

// Each model point goes to its nearest node; a node's height is the mean of
// its points. The nodes' phase is the first point's.
Lattice latticeOf(const Cloud& model, double cell) {
  Lattice l;
  l.cell = cell;
  if (model.empty()) return l;
  const double px = model[0].x() - cell * std::round(model[0].x() / cell);
  const double py = model[0].y() - cell * std::round(model[0].y() / cell);
  auto index = [&](double v, double phase) { return int(std::lround((v - phase) / cell)); };
  int i0 = INT32_MAX, j0 = INT32_MAX, i1 = INT32_MIN, j1 = INT32_MIN;
  for (const auto& p : model) {
    const int i = index(p.x(), px), j = index(p.y(), py);
    i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
  }
  l.x0 = px + i0 * cell, l.y0 = py + j0 * cell;
  l.cols = i1 - i0 + 1, l.rows = j1 - j0 + 1;
  std::vector<double> sum(std::size_t(l.cols) * std::size_t(l.rows), 0.0);
  std::vector<int> count(sum.size(), 0);
  for (const auto& p : model) {
    const auto k = std::size_t(index(p.y(), py) - j0) * std::size_t(l.cols) +
                   std::size_t(index(p.x(), px) - i0);
    sum[k] += p.z(), ++count[k];
  }
  l.z.assign(sum.size(), NAN);
  for (std::size_t k = 0; k < sum.size(); ++k)
    if (count[k] > 0) l.z[k] = sum[k] / count[k];
  return l;
}

// The levelled scan thinned to the mean of its points in squares of a
// quarter cell: turning these at each heading is far cheaper than turning
// every point. A cell's height is the mean of its patches, an area mean
// like the model's, and only cells the scan covers (almost) wholly are
// compared: where part of a cell is hidden behind an obstacle, the scan
// holds only the visible part's heights, the model the whole cell's.
constexpr int kPatchesPerCell = 16;
struct Patch {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double z = 0.0;
  int points = 0;
};

std::vector<Patch> patchesOf(const Cloud& levelled, double size) {
  std::unordered_map<std::int64_t, std::size_t> where;
  std::vector<Patch> patches;
  for (const auto& p : levelled) {
    const std::int64_t key = (std::int64_t(std::floor(p.x() / size)) << 32) ^
                             std::int64_t(std::uint32_t(std::int32_t(std::floor(p.y() / size))));
    const auto [it, added] = where.try_emplace(key, patches.size());
    if (added) patches.push_back({});
    Patch& patch = patches[it->second];
    patch.xy += p.head<2>(), patch.z += p.z(), ++patch.points;
  }
  for (auto& patch : patches) patch.xy /= patch.points, patch.z /= patch.points;
  return patches;
}

struct Placement {
  double score = INFINITY;  // height misfit over the scan's relief
  double yaw = 0.0;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  double dz = 0.0;
};

// Running sums of the height differences over an overlap.
struct Misfit {
  double sum = 0, sum2 = 0, scan = 0, scan2 = 0, n = 0;  // over the cells scored
  int overlap = 0;                                       // the scan's cells over model nodes
  void add(double model, double scan_z) {
    const double d = model - scan_z;
    sum += d, sum2 += d * d, scan += scan_z, scan2 += scan_z * scan_z, ++n;
  }
  double score() const {
    const double mean = sum / n;
    const double relief = scan2 / n - (scan / n) * (scan / n);
    return (sum2 / n - mean * mean) / std::max(relief, 1e-6);
  }
  double offset() const { return sum / n; }
};

// The scan binned into cells of the lattice's size: cell (i, j) holds the
// turned patches within half a cell of (i, j) cell - offset, and goes on the
// model's node (i + di, j + dj) when the scan is shifted by
// (x0, y0) + (di, dj) cell + offset.
struct ScanCells {
  std::vector<int> i, j;
  std::vector<double> z;
  std::vector<std::ptrdiff_t> at;      // j cols + i, cols the model's
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;  // index bounds
};

ScanCells binned(const std::vector<Patch>& patches, const Eigen::Matrix2d& turn,
                 const Eigen::Vector2d& offset, const Lattice& model, double min_coverage) {
  const double cell = model.cell;
  const double min_patches = min_coverage * kPatchesPerCell;
  double reach = 0;
  for (const auto& p : patches) reach = std::max(reach, p.xy.norm());
  const int half = int(std::ceil((reach + offset.norm()) / cell)) + 1, side = 2 * half + 1;
  std::vector<double> sum(std::size_t(side) * std::size_t(side), 0.0);
  std::vector<int> count(sum.size(), 0);
  for (const auto& p : patches) {
    const Eigen::Vector2d q = (turn * p.xy + offset) / cell;
    const auto k = std::size_t(std::lround(q.y()) + half) * std::size_t(side) +
                   std::size_t(std::lround(q.x()) + half);
    sum[k] += p.z, ++count[k];
  }
  ScanCells out;
  out.i0 = out.j0 = INT32_MAX, out.i1 = out.j1 = INT32_MIN;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const auto k = std::size_t(j) * std::size_t(side) + std::size_t(i);
      if (count[k] < min_patches) continue;
      out.i.push_back(i - half), out.j.push_back(j - half), out.z.push_back(sum[k] / count[k]);
      out.at.push_back(std::ptrdiff_t(j - half) * model.cols + (i - half));
      out.i0 = std::min(out.i0, i - half), out.i1 = std::max(out.i1, i - half);
      out.j0 = std::min(out.j0, j - half), out.j1 = std::max(out.j1, j - half);
    }
  return out;
}

Misfit misfitAt(const ScanCells& cells, const Lattice& model, int di, int dj) {
  Misfit m;
  const bool inside = cells.i0 + di >= 0 && cells.j0 + dj >= 0 && cells.i1 + di < model.cols &&
                      cells.j1 + dj < model.rows;
  if (inside) {  // no bounds to test: the bulk of the search
    const double* z = &model.z[std::size_t(dj) * std::size_t(model.cols) + std::size_t(di)];
    for (std::size_t k = 0; k < cells.z.size(); ++k)
      if (const double zm = z[cells.at[k]]; !std::isnan(zm)) m.add(zm, cells.z[k]);
    m.overlap = int(m.n);
    return m;
  }
  for (std::size_t k = 0; k < cells.z.size(); ++k) {
    const double z = model.node(cells.i[k] + di, cells.j[k] + dj);
    if (!std::isnan(z)) m.add(z, cells.z[k]), ++m.overlap;
  }
  return m;
}

// Keeps the `n` best placements that are not near a better one.
void keepBest(std::vector<Placement>& best, const Placement& p, int n, double cell,
              double yaw_step) {
  const auto near = [&](const Placement& q) {
    return (q.shift - p.shift).norm() < 2.5 * cell &&
           std::abs(std::remainder(q.yaw - p.yaw, 2 * M_PI)) < 3.5 * yaw_step;
  };
  for (auto& q : best)
    if (near(q)) {
      if (p.score < q.score) q = p;
      std::sort(best.begin(), best.end(),
                [](const Placement& a, const Placement& b) { return a.score < b.score; });
      return;
    }
  if (int(best.size()) == n && p.score >= best.back().score) return;
  best.push_back(p);
  std::sort(best.begin(), best.end(),
            [](const Placement& a, const Placement& b) { return a.score < b.score; });
  if (int(best.size()) > n) best.pop_back();
}

// Counts of a scan's cells in rectangles of cell indices, from 2-D prefix
// sums: an upper bound of a shift's overlap before it is scored.
class CellCounts {
 public:
  explicit CellCounts(const ScanCells& cells)
      : i0_(cells.i0), j0_(cells.j0), cols_(cells.i1 - cells.i0 + 2) {
    sums_.assign(std::size_t(cols_) * std::size_t(cells.j1 - cells.j0 + 2), 0);
    for (std::size_t k = 0; k < cells.z.size(); ++k)
      ++sums_[index(cells.i[k] - i0_ + 1, cells.j[k] - j0_ + 1)];
    for (int j = 1; j < int(sums_.size()) / cols_; ++j)
      for (int i = 1; i < cols_; ++i)
        sums_[index(i, j)] +=
            sums_[index(i - 1, j)] + sums_[index(i, j - 1)] - sums_[index(i - 1, j - 1)];
  }
  // Cells with i in [ia, ib] and j in [ja, jb] (bounds within the scan's).
  int in(int ia, int ib, int ja, int jb) const {
    if (ia > ib || ja > jb) return 0;
    ia -= i0_, ib -= i0_ - 1, ja -= j0_, jb -= j0_ - 1;
    return sums_[index(ib, jb)] - sums_[index(ia, jb)] - sums_[index(ib, ja)] +
           sums_[index(ia, ja)];
  }

 private:
  std::size_t index(int i, int j) const { return std::size_t(j) * std::size_t(cols_) + i; }
  int i0_, j0_, cols_;
  std::vector<int> sums_;
};

// Every shift by whole cells of `cells` (binned with `offset`) that puts
// enough of them over the lattice.
void matchShifts(const ScanCells& cells, const Lattice& model, double yaw,
                 const Eigen::Vector2d& offset, const GlobalOptions& o,
                 std::vector<Placement>& best) {
  const int needed = std::max(int(o.min_overlap * double(cells.z.size())), 10);
  const CellCounts counts(cells);
  const double yaw_step = o.yaw_step_deg * M_PI / 180;
  for (int dj = -cells.j1; dj < model.rows - cells.j0; ++dj)
    for (int di = -cells.i1; di < model.cols - cells.i0; ++di) {
      if (counts.in(std::max(cells.i0, -di), std::min(cells.i1, model.cols - 1 - di),
                    std::max(cells.j0, -dj), std::min(cells.j1, model.rows - 1 - dj)) < needed)
        continue;
      const Misfit m = misfitAt(cells, model, di, dj);
      if (m.overlap < needed) continue;
      const Eigen::Vector2d shift(model.x0 + di * model.cell + offset.x(),
                                  model.y0 + dj * model.cell + offset.y());
      keepBest(best, {m.score(), yaw, shift, m.offset()}, o.candidates, model.cell, yaw_step);
    }
}

// misfitAt() over the cells whose height differences are closest to their
// median, a fraction `keep` of them: a cell partly hidden from the sensor
// holds only its visible part's heights (an obstacle's top), the model the
// whole cell's mean.
Misfit trimmedMisfitAt(const ScanCells& cells, const Lattice& model, int di, int dj, double keep) {
  std::vector<std::pair<double, double>> pairs;  // model, scan
  for (std::size_t k = 0; k < cells.z.size(); ++k) {
    const double z = model.node(cells.i[k] + di, cells.j[k] + dj);
    if (!std::isnan(z)) pairs.emplace_back(z, cells.z[k]);
  }
  if (pairs.empty()) return {};
  auto gap = [](const std::pair<double, double>& p) { return p.first - p.second; };
  const auto middle = pairs.begin() + std::ptrdiff_t(pairs.size() / 2);
  std::nth_element(pairs.begin(), middle, pairs.end(),
                   [&](const auto& a, const auto& b) { return gap(a) < gap(b); });
  const double median = gap(*middle);
  const auto kept = pairs.begin() + std::ptrdiff_t(keep * double(pairs.size()));
  std::nth_element(pairs.begin(), kept, pairs.end(), [&](const auto& a, const auto& b) {
    return std::abs(gap(a) - median) < std::abs(gap(b) - median);
  });
  Misfit m;
  for (auto it = pairs.begin(); it != kept; ++it) m.add(it->first, it->second);
  m.overlap = int(pairs.size());
  return m;
}

// The best placement on a 5 x 5 x 5 grid of headings and shifts around
// `p`, spaced by `yaw_step` and `shift_step`, the scan binned afresh at each.
Placement searchAround(const std::vector<Patch>& patches, const Lattice& model, const Placement& p,
                       double yaw_step, double shift_step, const GlobalOptions& o) {
  Placement best = p;
  best.score = INFINITY;
  for (int a = -2; a <= 2; ++a) {
    const double yaw = p.yaw + a * yaw_step;
    const Eigen::Matrix2d turn = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    for (int v = -2; v <= 2; ++v)
      for (int u = -2; u <= 2; ++u) {
        const Eigen::Vector2d shift = p.shift + Eigen::Vector2d(u, v) * shift_step;
        const Eigen::Vector2d from_node = shift - Eigen::Vector2d(model.x0, model.y0);
        const Eigen::Vector2d whole = (from_node / model.cell).array().floor();
        const auto cells =
            binned(patches, turn, from_node - whole * model.cell, model, o.min_cell_coverage);
        const Misfit m =
            trimmedMisfitAt(cells, model, int(whole.x()), int(whole.y()), o.trimmed_fraction);
        if (m.overlap < std::max(o.min_overlap * double(cells.z.size()), 10.0)) continue;
        if (const double s = m.score(); s < best.score) best = {s, yaw, shift, m.offset()};
      }
  }
  return best;
}

// A finer search around a candidate: within a heading step and half a
// cell, then within a quarter of those.
Placement refined(const std::vector<Patch>& patches, const Lattice& model, const Placement& p,
                  const GlobalOptions& o) {
  const double yaw_step = o.yaw_step_deg * M_PI / 180;
  const Placement coarse = searchAround(patches, model, p, yaw_step / 2, model.cell / 4, o);
  if (!std::isfinite(coarse.score)) return coarse;
  return searchAround(patches, model, coarse, yaw_step / 8, model.cell / 16, o);
}

RegistrationOptions refineInMetres(const GlobalOptions& o) {
  RegistrationOptions r = o.refine;
  for (double* length :
       {&r.voxel_m, &r.source_voxel_m, &r.min_thickness_m, &r.max_distance_m, &r.min_distance_m,
        &r.min_step, &r.partner_distance_m, &r.partner_plane_m, &r.max_rms_m, &r.sigma_floor_m,
        &r.agreement_tolerance_m, &r.degenerate_sigma_m, &r.doubtful_sigma_m})
    *length *= o.cell_m;
  for (double* length : {&r.search.cell_m, &r.search.max_shift_m, &r.search.truncation_m})
    *length *= o.cell_m;
  return r;
}

}  // namespace

Eigen::Matrix3d withoutYaw(const Eigen::Matrix3d& sensor_to_world) {
  const double yaw = std::atan2(sensor_to_world(1, 0), sensor_to_world(0, 0));
  return Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * sensor_to_world;
}

void validate(const GlobalOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("localization option " + what);
  };
  require(o.cell_m > 0 && o.cell_m <= 1e5, "cell_m must be in (0, 100 km]");
  require(o.yaw_step_deg > 0 && o.yaw_step_deg <= 45, "yaw_step_deg must be in (0, 45]");
  require(o.min_overlap > 0 && o.min_overlap <= 1, "min_overlap must be in (0, 1]");
  require(o.min_cell_coverage > 0 && o.min_cell_coverage <= 1,
          "min_cell_coverage must be in (0, 1]");
  require(o.candidates >= 1 && o.candidates <= 100, "candidates must be in [1, 100]");
  require(o.trimmed_fraction >= 0.5 && o.trimmed_fraction <= 1,
          "trimmed_fraction must be in [0.5, 1]");
  validate(refineInMetres(o));
}

std::optional<Registration> localize(const Cloud& scan, const Eigen::Matrix3d& tilt,
                                     const Cloud& model, const GlobalOptions& o) {
  validate(o);
  for (const auto* cloud : {&scan, &model})
    for (const auto& p : *cloud)
      if (!p.allFinite()) throw std::invalid_argument("localization: a point is not finite");
  const Lattice lattice = latticeOf(model, o.cell_m);
  Cloud levelled;
  for (const auto& p : scan) levelled.push_back(tilt * p);
  const auto patches = patchesOf(levelled, o.cell_m / 4);  // kPatchesPerCell
  const double yaw_step = o.yaw_step_deg * M_PI / 180;
  if (const auto cells = binned(patches, Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(),
                                lattice, o.min_cell_coverage);
      cells.z.size() < 10)
    throw std::invalid_argument("localization: the scan covers " + std::to_string(cells.z.size()) +
                                " cells; at least 10 needed");
  const int headings = int(std::ceil(360.0 / o.yaw_step_deg - 1e-9));
  // Each heading's best placements, merged in heading order so that the
  // result does not depend on the threads' schedule.
  std::vector<std::vector<Placement>> by_heading(static_cast<std::size_t>(headings));
#pragma omp parallel for schedule(dynamic)
  for (int h = 0; h < headings; ++h) {
    const double yaw = h * yaw_step;
    const Eigen::Matrix2d turn = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    // Whole-cell shifts, and half-cell ones by binning the scan offset.
    for (const double ox : {0.0, 0.5})
      for (const double oy : {0.0, 0.5}) {
        const Eigen::Vector2d offset = Eigen::Vector2d(ox, oy) * o.cell_m;
        const auto cells = binned(patches, turn, offset, lattice, o.min_cell_coverage);
        if (cells.z.size() >= 10)
          matchShifts(cells, lattice, yaw, offset, o, by_heading[std::size_t(h)]);
      }
  }
  std::vector<Placement> best;
  for (const auto& placements : by_heading)
    for (const auto& p : placements) keepBest(best, p, o.candidates, o.cell_m, yaw_step);
  if (best.empty()) return std::nullopt;
  std::vector<Placement> refinements(best.size());
#pragma omp parallel for schedule(dynamic)
  for (std::size_t k = 0; k < best.size(); ++k)
    refinements[k] = refined(patches, lattice, best[k], o);
  Placement winner;
  for (const auto& r : refinements)
    if (r.score < winner.score) winner = r;
  if (!std::isfinite(winner.score)) return std::nullopt;
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(winner.shift.x(), winner.shift.y(), winner.dz);
  start.linear() =
      Eigen::AngleAxisd(winner.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * tilt;
  return registerClouds(scan, model, start, refineInMetres(o));
}

}  // namespace ambler::mapping

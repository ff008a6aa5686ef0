#include "mapping/HeightSearch.h"

#include <omp.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/Angles.h"

namespace ambler::mapping {

namespace {

// Mean height per cell over the points' extent; NaN where no point fell.
struct HeightGrid {
  double cell = 0, x0 = 0, y0 = 0;
  int cols = 0, rows = 0;
  std::vector<float> z;

  // The cell of a point within the grid's extent.
  std::size_t indexOf(const Eigen::Vector3d& p) const {
    return std::size_t(int((p.y() - y0) / cell)) * std::size_t(cols) +
           std::size_t(int((p.x() - x0) / cell));
  }
  float cellAt(int c, int r) const {
    if (c < 0 || r < 0 || c >= cols || r >= rows) return std::numeric_limits<float>::quiet_NaN();
    return z[std::size_t(r) * std::size_t(cols) + std::size_t(c)];
  }
  // Height (and its gradient) bilinear between the four cells' centres
  // around xy; false where one of them is unknown.
  bool bilinear(const Eigen::Vector2d& xy, double& height, Eigen::Vector2d* gradient) const {
    const double u = (xy.x() - x0) / cell - 0.5, v = (xy.y() - y0) / cell - 0.5;
    const int c = int(std::floor(u)), r = int(std::floor(v));
    const double fu = u - c, fv = v - r;
    double z00, z10, z01, z11;
    if (c >= 0 && r >= 0 && c + 1 < cols && r + 1 < rows) {  // the search's usual case
      const float* row = &z[std::size_t(r) * std::size_t(cols) + std::size_t(c)];
      z00 = row[0], z10 = row[1], z01 = row[cols], z11 = row[cols + 1];
    } else {
      z00 = cellAt(c, r), z10 = cellAt(c + 1, r), z01 = cellAt(c, r + 1),
      z11 = cellAt(c + 1, r + 1);
    }
    if (std::isnan(z00 + z10 + z01 + z11)) return false;
    height = (1 - fv) * ((1 - fu) * z00 + fu * z10) + fv * ((1 - fu) * z01 + fu * z11);
    if (gradient)
      *gradient = Eigen::Vector2d((1 - fv) * (z10 - z00) + fv * (z11 - z01),
                                  (1 - fu) * (z01 - z00) + fu * (z11 - z10)) /
                  cell;
    return true;
  }
  // Bilinear where it can be, else the height of the cell xy falls in.
  float at(const Eigen::Vector2d& xy) const {
    double height = 0;
    if (bilinear(xy, height, nullptr)) return float(height);
    return cellAt(int(std::floor((xy.x() - x0) / cell)), int(std::floor((xy.y() - y0) / cell)));
  }
};

HeightGrid gridOf(const std::vector<Eigen::Vector3d>& points, double cell) {
  HeightGrid g;
  g.cell = cell;
  Eigen::Vector2d lo = points.front().head<2>(), hi = lo;
  for (const auto& p : points) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  g.x0 = lo.x(), g.y0 = lo.y();
  const double cols = (hi.x() - lo.x()) / cell + 1, rows = (hi.y() - lo.y()) / cell + 1;
  if (cols * rows > 1e8)
    throw std::invalid_argument("height grid: the cloud spans " + std::to_string(int(cols)) +
                                " x " + std::to_string(int(rows)) + " cells of " +
                                std::to_string(cell) + " m; at most 1e8");
  g.cols = int(cols), g.rows = int(rows);
  std::vector<double> sum(std::size_t(g.cols) * std::size_t(g.rows), 0.0);
  std::vector<int> count(sum.size(), 0);
  for (const auto& p : points) {
    const auto i = g.indexOf(p);
    sum[i] += p.z(), ++count[i];
  }
  g.z.assign(sum.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < sum.size(); ++i)
    if (count[i] > 0) g.z[i] = float(sum[i] / count[i]);
  return g;
}

// The source's cells: the mean of the points in each.
std::vector<Eigen::Vector3d> cellMeans(const std::vector<Eigen::Vector3d>& points, double cell) {
  const HeightGrid grid = gridOf(points, cell);
  std::vector<Eigen::Vector3d> sum(grid.z.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(grid.z.size(), 0);
  for (const auto& p : points) {
    const auto i = grid.indexOf(p);
    sum[i] += p, ++count[i];
  }
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < sum.size(); ++i)
    if (count[i] > 0) out.push_back(sum[i] / count[i]);
  return out;
}

// Each cell's distance to the nearest cell without height [cells]
// (two-pass chamfer, 1 and sqrt 2).
std::vector<float> distanceToHoles(const HeightGrid& g) {
  const float inf = 1e9f, diagonal = float(std::sqrt(2.0));
  std::vector<float> d(g.z.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = std::isnan(g.z[i]) ? 0.0f : inf;
  auto at = [&](int c, int r) -> float {
    if (c < 0 || r < 0 || c >= g.cols || r >= g.rows) return 0.0f;  // off the grid: a hole
    return d[std::size_t(r) * std::size_t(g.cols) + std::size_t(c)];
  };
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      float& v = d[std::size_t(r) * std::size_t(g.cols) + std::size_t(c)];
      v = std::min({v, at(c - 1, r) + 1, at(c, r - 1) + 1, at(c - 1, r - 1) + diagonal,
                    at(c + 1, r - 1) + diagonal});
    }
  for (int r = g.rows - 1; r >= 0; --r)
    for (int c = g.cols - 1; c >= 0; --c) {
      float& v = d[std::size_t(r) * std::size_t(g.cols) + std::size_t(c)];
      v = std::min({v, at(c + 1, r) + 1, at(c, r + 1) + 1, at(c + 1, r + 1) + diagonal,
                    at(c - 1, r + 1) + diagonal});
    }
  return d;
}

// The source cells that stay over known target heights at every placement
// searched: every placement is then scored on the same cells, and none
// wins by moving the hard ones (a rock's edge, a shadow's) off the cover.
// All of them when too few are left.
std::vector<Eigen::Vector3d> alwaysCovered(const std::vector<Eigen::Vector3d>& cells,
                                           const HeightGrid& grid, const Eigen::Vector2d& centre,
                                           const HeightSearchOptions& o) {
  const auto holes = distanceToHoles(grid);
  std::vector<Eigen::Vector3d> out;
  for (const auto& c : cells) {
    const int col = int(std::floor((c.x() - grid.x0) / grid.cell)),
              row = int(std::floor((c.y() - grid.y0) / grid.cell));
    if (col < 0 || row < 0 || col >= grid.cols || row >= grid.rows) continue;
    const double margin = (c.head<2>() - centre).norm() * o.max_turn_deg * kDeg +
                          std::sqrt(2.0) * o.max_shift_m + 2 * o.cell_m;
    if (holes[std::size_t(row) * std::size_t(grid.cols) + std::size_t(col)] * grid.cell >= margin)
      out.push_back(c);
  }
  return out.size() >= 200 && out.size() * 5 >= cells.size() ? out : cells;
}

struct Placement {
  double yaw = 0, dx = 0, dy = 0;
  Eigen::Vector3d tilt = Eigen::Vector3d::Zero();  // a, b, c: dz = a x + b y + c about the centre
  double score = std::numeric_limits<double>::infinity();
};

// Height differences of the placed source cells against the grid, the best
// plane through them removed, truncated, averaged over the cells the target
// covers (counting the others against a placement drags it towards more
// overlap: views of different ground always overlap only in part).
Placement scored(const std::vector<Eigen::Vector3d>& cells, const HeightGrid& grid,
                 const Eigen::Vector2d& centre, Placement p, double tau) {
  const Eigen::Matrix2d turn = Eigen::Rotation2Dd(p.yaw).toRotationMatrix();
  const Eigen::Vector2d shift(p.dx, p.dy);
  std::vector<Eigen::Vector4d> pairs;  // x, y about the centre, 1, difference
  pairs.reserve(cells.size());
  // The normal equations of the plane (x, y, 1): its six distinct sums.
  double sxx = 0, sxy = 0, sx = 0, syy = 0, sy = 0, n = 0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& c : cells) {
    const Eigen::Vector2d xy = turn * (c.head<2>() - centre) + shift;
    const float zt = grid.at(xy + centre);
    if (std::isnan(zt)) continue;
    const double x = xy.x(), y = xy.y(), r = double(zt) - c.z();
    sxx += x * x, sxy += x * y, sx += x, syy += y * y, sy += y, n += 1;
    b += Eigen::Vector3d(x, y, 1.0) * r;
    pairs.emplace_back(x, y, 1.0, r);
  }
  if (pairs.size() < 50 || pairs.size() * 4 < cells.size()) return p;
  Eigen::Matrix3d a;
  a << sxx, sxy, sx, sxy, syy, sy, sx, sy, n;
  p.tilt = a.ldlt().solve(b);
  double sum = 0;
  for (const auto& q : pairs)
    sum += std::min(std::pow(q[3] - q.head<3>().dot(p.tilt), 2), tau * tau);
  p.score = sum / double(pairs.size());
  return p;
}

Placement bestAround(const std::vector<Eigen::Vector3d>& cells, const HeightGrid& grid,
                     const Eigen::Vector2d& centre, const Placement& around, double yaw_span,
                     double yaw_step, double shift_span, double shift_step, double tau) {
  const int ny = int(std::round(yaw_span / yaw_step)),
            ns = int(std::round(shift_span / shift_step));
  const int side = 2 * ns + 1, count = (2 * ny + 1) * side * side;
  std::vector<Placement> tried(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(dynamic, 8)
  for (int k = 0; k < count; ++k) {
    Placement p = around;
    p.yaw += (k / (side * side) - ny) * yaw_step;
    p.dx += ((k / side) % side - ns) * shift_step;
    p.dy += (k % side - ns) * shift_step;
    tried[std::size_t(k)] = scored(cells, grid, centre, p, tau);
  }
  Placement best = around;
  for (const auto& p : tried)
    if (p.score < best.score) best = p;
  return best;
}

// The turn by the rotation vector `turn` about `pivot`, then `shift`.
Eigen::Isometry3d turnAbout(const Eigen::Vector3d& turn, const Eigen::Vector3d& pivot,
                            const Eigen::Vector3d& shift) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (turn.norm() > 0)
    t.linear() = Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix();
  t.translation() = pivot - t.linear() * pivot + shift;
  return t;
}

// Gauss-Newton on the cells' height differences, six degrees of freedom,
// each difference weighted by a Geman-McClure kernel of the truncation
// scale: the search's grid of shifts and turns made continuous.
Eigen::Isometry3d refineHeights(const std::vector<Eigen::Vector3d>& cells, const HeightGrid& grid,
                                const Eigen::Vector3d& pivot, Eigen::Isometry3d motion,
                                double scale) {
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  for (int iteration = 0; iteration < 30; ++iteration) {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
    Vector6d g = Vector6d::Zero();
    int used = 0;
    for (const auto& c : cells) {
      const Eigen::Vector3d p = motion * c;
      double zt = 0;
      Eigen::Vector2d grad;
      if (!grid.bilinear(p.head<2>(), zt, &grad)) continue;
      const double r = zt - p.z();
      const double w = 1.0 / std::pow(1.0 + r * r / (scale * scale), 2);
      const Eigen::Vector3d q = p - pivot;
      // d(residual)/d(turn, shift) of p -> p + turn x q + shift.
      Vector6d j;
      j << -grad.y() * q.z() - q.y(), grad.x() * q.z() + q.x(), grad.y() * q.x() - grad.x() * q.y(),
          grad.x(), grad.y(), -1.0;
      h += w * j * j.transpose();
      g += w * j * r;
      ++used;
    }
    if (used < 50) return motion;
    const Vector6d step =
        -(h + 1e-9 * h.trace() * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(g);
    if (!step.allFinite()) return motion;
    motion = turnAbout(step.head<3>(), pivot, step.tail<3>()) * motion;
    if (step.head<3>().norm() < 1e-6 && step.tail<3>().norm() < 1e-5) break;
  }
  return motion;
}

}  // namespace

Eigen::Isometry3d searchHeights(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<Eigen::Vector3d>& target,
                                const HeightSearchOptions& o) {
  if (source.empty() || target.empty()) return Eigen::Isometry3d::Identity();
  const HeightGrid grid = gridOf(target, o.cell_m);
  auto cells = cellMeans(source, o.cell_m);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : cells) mean += c;
  mean /= double(cells.size());
  const Eigen::Vector2d centre = mean.head<2>();
  cells = alwaysCovered(cells, grid, centre, o);
  // The wide search on every third cell, a narrower one on all of them.
  std::vector<Eigen::Vector3d> some;
  for (std::size_t i = 0; i < cells.size(); i += 3) some.push_back(cells[i]);
  Placement best = scored(some, grid, centre, {}, o.truncation_m);
  best = bestAround(some, grid, centre, best, o.max_turn_deg * kDeg, 0.5 * kDeg, o.max_shift_m,
                    o.cell_m / 2, o.truncation_m);
  best.score = std::numeric_limits<double>::infinity();
  best = bestAround(cells, grid, centre, best, 0.5 * kDeg, 0.25 * kDeg, o.cell_m / 2, o.cell_m / 4,
                    o.truncation_m);
  if (!std::isfinite(best.score)) return Eigen::Isometry3d::Identity();
  // Turn and shift about the cells' centre, then the tilt as a small turn
  // about it: dz = a x + b y is the turn (b, -a, 0).
  const Eigen::Vector3d pivot(centre.x(), centre.y(), mean.z());
  const Eigen::Isometry3d turn = turnAbout({0, 0, best.yaw}, pivot, {best.dx, best.dy, 0});
  const Eigen::Isometry3d level =
      turnAbout({best.tilt.y(), -best.tilt.x(), 0}, pivot, {0, 0, best.tilt.z()});
  return refineHeights(cells, grid, pivot, level * turn, o.truncation_m / 2);
}

double heightAgreement(const std::vector<Eigen::Vector3d>& source,
                       const std::vector<Eigen::Vector3d>& target, double cell_m,
                       double tolerance_m) {
  if (source.empty() || target.empty()) return std::numeric_limits<double>::quiet_NaN();
  const HeightGrid grid = gridOf(target, cell_m);
  int over = 0, agree = 0;
  for (const auto& c : cellMeans(source, cell_m)) {
    const float z = grid.at(c.head<2>());
    if (std::isnan(z)) continue;
    ++over;
    agree += std::abs(double(z) - c.z()) <= tolerance_m;
  }
  return over == 0 ? std::numeric_limits<double>::quiet_NaN() : double(agree) / over;
}

}  // namespace ambler::mapping

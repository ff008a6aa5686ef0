#include "sim/RayCaster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ambler::sim {

RayCaster::RayCaster(const Terrain& terrain, RayCasterOptions options)
    : terrain_(terrain), options_(options), extent_(terrain.extent()) {
  const double cell = options_.cell_size;
  cols_ = std::max(1, int(std::ceil(extent_.width() / cell)));
  rows_ = std::max(1, int(std::ceil(extent_.height() / cell)));
  bin_max_.resize(std::size_t(cols_) * rows_);
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      const Box2 bin{extent_.x_min + c * cell, extent_.y_min + r * cell,
                     std::min(extent_.x_min + (c + 1) * cell, extent_.x_max),
                     std::min(extent_.y_min + (r + 1) * cell, extent_.y_max)};
      bin_max_[std::size_t(r) * cols_ + c] = terrain_.maxHeightIn(bin);
    }
  top_ = *std::max_element(bin_max_.begin(), bin_max_.end());
}

double RayCaster::groundGap(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t) const {
  const Eigen::Vector3d p = o + t * d;
  return p.z() - terrain_.height(p.x(), p.y());
}

std::optional<double> RayCaster::cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                      double max_range) const {
  // Clip the ray to the terrain's extent.
  const auto inside = extent_.lineInterval(o.head<2>(), d.head<2>(), max_range);
  if (!inside) return std::nullopt;
  auto [t0, t1] = *inside;
  // Nothing is hit above the terrain's top: a ray from high above starts
  // just over it rather than crossing bin after bin of empty space.
  const double above_top = top_ + 0.01;
  if (d.z() < 0 && o.z() > above_top) t0 = std::max(t0, (above_top - o.z()) / d.z());
  if (t0 >= t1) return std::nullopt;

  // Walk the upper-bound bins the ray crosses (Amanatides-Woo).
  const double cell = options_.cell_size;
  const Eigen::Vector3d start = o + t0 * d;
  int ix = std::clamp(int((start.x() - extent_.x_min) / cell), 0, cols_ - 1);
  int iy = std::clamp(int((start.y() - extent_.y_min) / cell), 0, rows_ - 1);
  const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  auto next_boundary = [&](int i, int step, double origin, double p, double dir) {
    if (std::abs(dir) < 1e-12) return inf;
    const double boundary = origin + (i + (step > 0 ? 1 : 0)) * cell;
    return t0 + (boundary - p) / dir;
  };
  double t_next_x = next_boundary(ix, step_x, extent_.x_min, start.x(), d.x());
  double t_next_y = next_boundary(iy, step_y, extent_.y_min, start.y(), d.y());
  const double dt_x = std::abs(d.x()) < 1e-12 ? inf : cell / std::abs(d.x());
  const double dt_y = std::abs(d.y()) < 1e-12 ? inf : cell / std::abs(d.y());

  double prev_t = t0, prev_gap = groundGap(o, d, t0);
  if (prev_gap <= 0.0) return std::nullopt;  // starts below the ground
  double ta = t0;
  while (ta < t1 && ix >= 0 && iy >= 0 && ix < cols_ && iy < rows_) {
    const double tb = std::min({t_next_x, t_next_y, t1});
    const double z_low = std::min(o.z() + ta * d.z(), o.z() + tb * d.z());
    if (z_low > bin_max_[std::size_t(iy) * cols_ + ix]) {
      prev_t = tb;
      prev_gap = inf;  // above everything in this bin
    } else {
      for (double t = std::min(ta + options_.step, tb);; t = std::min(t + options_.step, tb)) {
        const double gap = groundGap(o, d, t);
        if (prev_gap > 0.0 && gap <= 0.0) {
          double a = prev_t, b = t;
          for (int i = 0; i < 48 && b - a > options_.tolerance; ++i) {
            const double m = 0.5 * (a + b);
            (groundGap(o, d, m) > 0.0 ? a : b) = m;
          }
          return b;
        }
        prev_t = t;
        prev_gap = std::isnan(gap) ? -inf : gap;  // holes never start a hit
        if (t >= tb) break;
      }
    }
    ta = tb;
    if (t_next_x < t_next_y) {
      ix += step_x;
      t_next_x += dt_x;
    } else {
      iy += step_y;
      t_next_y += dt_y;
    }
  }
  return std::nullopt;
}

}  // namespace ambler::sim

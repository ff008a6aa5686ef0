#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

namespace ambler {

// Axis-aligned rectangle in the x-y plane of some frame [m].
struct Box2 {
  double x_min = 0.0;
  double y_min = 0.0;
  double x_max = 0.0;
  double y_max = 0.0;

  bool contains(double x, double y) const {
    return x >= x_min && x <= x_max && y >= y_min && y <= y_max;
  }
  double width() const { return x_max - x_min; }
  double height() const { return y_max - y_min; }
  Box2 bounds() const { return *this; }

  // The stretch [t_in, t_out] of origin + t dir, t in [0, t_max], that lies
  // in the box (the slab test); none when the line misses it there.
  std::optional<std::pair<double, double>> lineInterval(const Eigen::Vector2d& origin,
                                                        const Eigen::Vector2d& dir,
                                                        double t_max) const {
    double t_in = 0.0, t_out = t_max;
    const double lo[2] = {x_min, y_min}, hi[2] = {x_max, y_max};
    for (int a = 0; a < 2; ++a) {
      if (std::abs(dir[a]) < 1e-12) {
        if (origin[a] < lo[a] || origin[a] > hi[a]) return std::nullopt;
        continue;
      }
      double ta = (lo[a] - origin[a]) / dir[a], tb = (hi[a] - origin[a]) / dir[a];
      if (ta > tb) std::swap(ta, tb);
      t_in = std::max(t_in, ta);
      t_out = std::min(t_out, tb);
    }
    if (t_in > t_out) return std::nullopt;
    return std::pair{t_in, t_out};
  }
};

struct Cell {
  int row = 0;
  int col = 0;
};

// A regular grid on the x-y plane. Cell (r, c) has its centre at
// (origin_x + (c + 0.5) * resolution, origin_y + (r + 0.5) * resolution):
// row index grows with y, column index with x. Every map and ground-truth
// raster of the project uses this convention (docs/formats.md).
struct GridSpec {
  double origin_x = 0.0;
  double origin_y = 0.0;
  double resolution = 0.1;
  int rows = 0;
  int cols = 0;

  Eigen::Vector2d cellCenter(int r, int c) const {
    return {origin_x + (c + 0.5) * resolution, origin_y + (r + 0.5) * resolution};
  }
  Box2 bounds() const {
    return {origin_x, origin_y, origin_x + cols * resolution, origin_y + rows * resolution};
  }
  int cellCount() const { return rows * cols; }
  bool hasCell(int r, int c) const { return r >= 0 && r < rows && c >= 0 && c < cols; }
  int index(int r, int c) const { return r * cols + c; }
  // The cell containing (x, y), if any; cells own their lower edges.
  std::optional<Cell> cellAt(double x, double y) const {
    const double c = std::floor((x - origin_x) / resolution);
    const double r = std::floor((y - origin_y) / resolution);
    if (!(c >= 0 && c < cols && r >= 0 && r < rows)) return std::nullopt;
    return Cell{int(r), int(c)};
  }

  // The smallest grid at `resolution` that covers `box`.
  static GridSpec covering(const Box2& box, double resolution);
  // This grid's cells that overlap `box`, on the same lattice; no cells
  // when none do.
  GridSpec window(const Box2& box) const;
};

inline GridSpec GridSpec::covering(const Box2& box, double resolution) {
  GridSpec g;
  g.origin_x = box.x_min;
  g.origin_y = box.y_min;
  g.resolution = resolution;
  g.cols = static_cast<int>(std::ceil(box.width() / resolution - 1e-9));
  g.rows = static_cast<int>(std::ceil(box.height() / resolution - 1e-9));
  return g;
}

inline GridSpec GridSpec::window(const Box2& box) const {
  const int c0 = std::max(0, static_cast<int>(std::floor((box.x_min - origin_x) / resolution)));
  const int r0 = std::max(0, static_cast<int>(std::floor((box.y_min - origin_y) / resolution)));
  const int c1 = std::min(cols, static_cast<int>(std::ceil((box.x_max - origin_x) / resolution)));
  const int r1 = std::min(rows, static_cast<int>(std::ceil((box.y_max - origin_y) / resolution)));
  GridSpec w = *this;
  w.origin_x = origin_x + c0 * resolution;
  w.origin_y = origin_y + r0 * resolution;
  w.cols = std::max(0, c1 - c0);
  w.rows = std::max(0, r1 - r0);
  return w;
}

}  // namespace ambler

#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/GridSpec.h"

namespace ambler {

// A simple polygon in the x-y plane (vertices in order, either winding, not
// closed explicitly) [m].
struct Polygon2 {
  std::vector<Eigen::Vector2d> vertices;

  // Crossing-number test; points on an edge may fall either side.
  bool contains(double x, double y) const {
    bool inside = false;
    const std::size_t n = vertices.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
      const auto& a = vertices[i];
      const auto& b = vertices[j];
      if ((a.y() > y) != (b.y() > y) && x < (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x())
        inside = !inside;
    }
    return inside;
  }
  Box2 bounds() const {
    Box2 box{INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (const auto& v : vertices)
      box = {std::min(box.x_min, v.x()), std::min(box.y_min, v.y()), std::max(box.x_max, v.x()),
             std::max(box.y_max, v.y())};
    return box;
  }
};

// A disk in the x-y plane: a foot, a sampling radius [m].
struct Disk {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.0;

  bool contains(double x, double y) const {
    return (Eigen::Vector2d(x, y) - center).squaredNorm() <= radius * radius;
  }
  Box2 bounds() const {
    return {center.x() - radius, center.y() - radius, center.x() + radius, center.y() + radius};
  }
};

// Calls f(row, col) for every cell of `grid` whose centre lies in `region`
// (a Box2, Polygon2 or Disk: anything with bounds() and contains(x, y)),
// row by row. Only the cells under the region's bounding box are visited.
template <typename Region, typename F>
void forEachCellIn(const GridSpec& grid, const Region& region, F&& f) {
  const Box2 b = region.bounds();
  const double res = grid.resolution;
  // Cell c has its centre inside [x_min, x_max] for c in [c_first, c_last].
  const int c_first = std::max(0, int(std::ceil((b.x_min - grid.origin_x) / res - 0.5)));
  const int c_last =
      std::min(grid.cols - 1, int(std::floor((b.x_max - grid.origin_x) / res - 0.5)));
  const int r_first = std::max(0, int(std::ceil((b.y_min - grid.origin_y) / res - 0.5)));
  const int r_last =
      std::min(grid.rows - 1, int(std::floor((b.y_max - grid.origin_y) / res - 0.5)));
  for (int r = r_first; r <= r_last; ++r)
    for (int c = c_first; c <= c_last; ++c) {
      const Eigen::Vector2d p = grid.cellCenter(r, c);
      if (region.contains(p.x(), p.y())) f(r, c);
    }
}

}  // namespace ambler

#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/GridSpec.h"
#include "io/Image.h"

namespace ambler::sim {

// The ground the simulator's sensors look at: a height function z(x, y) in
// the world frame (z up) over a rectangular extent.
class Terrain {
 public:
  virtual ~Terrain() = default;

  // Exact ground height [m]; NaN outside extent().
  virtual double height(double x, double y) const = 0;

  // An upper bound of height() over `box` (need not be tight). The ray
  // caster skips space above it.
  virtual double maxHeightIn(const Box2& box) const = 0;

  virtual Box2 extent() const = 0;
};

// Thrown where the simulation needs ground the terrain has no height for:
// the rover or the scanner set down over a terrain model's no-data.
class NoGroundError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The NoGroundError of `what` ("the scanner", "foot 3") set down at `xy`
// over `terrain`: off its extent, or over a terrain model's no-data.
inline NoGroundError noGroundAtStart(const std::string& what, const Eigen::Vector2d& xy,
                                     const Terrain& terrain) {
  const Box2 e = terrain.extent();
  char text[256];
  if (!e.contains(xy.x(), xy.y()))
    std::snprintf(text, sizeof text,
                  " at (%.6g, %.6g) m, where the rover starts: off the terrain, which spans x "
                  "%.6g..%.6g m, y %.6g..%.6g m",
                  xy.x(), xy.y(), e.x_min, e.x_max, e.y_min, e.y_max);
  else
    std::snprintf(text, sizeof text,
                  " at (%.2f, %.2f) m, where the rover starts (no-data in the terrain model; "
                  "start over data with --dtm-centre)",
                  xy.x(), xy.y());
  return NoGroundError("the terrain has no height under " + what + text);
}

// Heights at the centres of `grid`'s cells (NaN off the terrain).
inline io::FloatImage sampleHeights(const Terrain& terrain, const GridSpec& grid) {
  io::FloatImage z(grid.rows, grid.cols);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const auto p = grid.cellCenter(r, c);
      z(r, c) = float(terrain.height(p.x(), p.y()));
    }
  return z;
}

// A model from orbital altimetry at the grid's resolution: at each cell's
// centre, the cell's mean height over samples x samples points spread over
// it (rather than the height at the centre); cells reaching off the
// terrain are left out.
inline std::vector<Eigen::Vector3d> orbitalModel(const Terrain& terrain, const GridSpec& grid,
                                                 int samples = 4) {
  std::vector<Eigen::Vector3d> model;
  const double step = grid.resolution / samples;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const auto centre = grid.cellCenter(r, c);
      double sum = 0.0;
      for (int i = 0; i < samples; ++i)
        for (int j = 0; j < samples; ++j)
          sum += terrain.height(centre.x() + (i + 0.5 - 0.5 * samples) * step,
                                centre.y() + (j + 0.5 - 0.5 * samples) * step);
      if (std::isfinite(sum)) model.emplace_back(centre.x(), centre.y(), sum / (samples * samples));
    }
  return model;
}

}  // namespace ambler::sim

#include "terrain/Binning.h"

#include <cmath>
#include <vector>

namespace ambler::terrain {

ElevationMap buildBinnedMap(const sensor::RangeImage& image, const GridSpec& grid) {
  std::vector<double> sum_z(grid.cellCount(), 0.0), sum_var(grid.cellCount(), 0.0);
  std::vector<int> count(grid.cellCount(), 0);
  const Eigen::Vector3d origin = image.sensor_to_world.translation();
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c) {
      if (!image.hasReturn(r, c)) continue;
      const Eigen::Vector3d p = image.pointInWorld(r, c);
      const auto cell = grid.cellAt(p.x(), p.y());
      if (!cell) continue;
      const double rho = image.at(r, c);
      const double sigma =
          sensor::rangeSigma(rho, image.range_sigma_k) * std::abs(origin.z() - p.z()) / rho;
      const int i = grid.index(cell->row, cell->col);
      sum_z[i] += p.z();
      sum_var[i] += sigma * sigma;
      ++count[i];
    }
  ElevationMap map(grid, "world");
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const int i = grid.index(r, c);
      if (count[i] > 0)
        map.setKnown(r, c, sum_z[i] / count[i], std::sqrt(sum_var[i]) / count[i], float(count[i]));
    }
  return map;
}

}  // namespace ambler::terrain

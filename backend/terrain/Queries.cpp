#include "terrain/Queries.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ambler::terrain {

HeightEstimate heightAt(const ElevationMap& map, double x, double y) {
  const auto cell = map.grid().cellAt(x, y);
  if (!cell) return {};
  const auto state = map.state(cell->row, cell->col);
  if (state != CellState::kKnown) return {state};
  return {state, map.elevation(cell->row, cell->col), map.sigma(cell->row, cell->col)};
}

void RegionAccumulator::add(const ElevationMap& map, int r, int c) {
  switch (map.state(r, c)) {
    case CellState::kUnknown:
      ++s_.unknown;
      return;
    case CellState::kShadow:
      ++s_.shadow;
      return;
    case CellState::kKnown:
      break;
  }
  const double z = map.elevation(r, c), sigma = map.sigma(r, c);
  s_.min_z = s_.known ? std::min(s_.min_z, z) : z;
  s_.max_z = s_.known ? std::max(s_.max_z, z) : z;
  ++s_.known;
  sum_z_ += z;
  sum_var_ += sigma * sigma;
}

RegionSummary RegionAccumulator::result() const {
  RegionSummary s = s_;
  if (s.known > 0) {
    s.mean_z = sum_z_ / s.known;
    s.mean_sigma = std::sqrt(sum_var_) / s.known;
  }
  return s;
}

ElevationMap resample(const ElevationMap& map, double resolution) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw std::invalid_argument("resample: resolution must be a positive number of metres");
  const GridSpec target = GridSpec::covering(map.grid().bounds(), resolution);
  ElevationMap out(target, map.frame());
  for (int r = 0; r < target.rows; ++r)
    for (int c = 0; c < target.cols; ++c) {
      const auto centre = target.cellCenter(r, c);
      const double h = 0.5 * resolution;
      auto s = summarize(
          map, Box2{centre.x() - h, centre.y() - h, centre.x() + h - 1e-9, centre.y() + h - 1e-9});
      if (s.cells() == 0) {
        const auto e = heightAt(map, centre.x(), centre.y());
        if (e.state == CellState::kKnown)
          out.setKnown(r, c, e.z, e.sigma);
        else
          out.setUnobserved(r, c, e.state);
      } else if (s.known > 0) {
        out.setKnown(r, c, s.mean_z, s.mean_sigma, float(s.known));
      } else {
        out.setUnobserved(r, c, s.shadow > 0 ? CellState::kShadow : CellState::kUnknown);
      }
    }
  return out;
}

}  // namespace ambler::terrain

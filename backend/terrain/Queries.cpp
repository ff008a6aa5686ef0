#include "terrain/Queries.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ambler::terrain {

HeightEstimate heightAt(const ElevationMap& map, double x, double y) {
  const auto cell = map.grid().cellAt(x, y);
  if (!cell) return {};
  const auto state = map.state(cell->row, cell->col);
  if (!hasHeight(state)) return {state};
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
    case CellState::kOblique:
      break;
  }
  const double z = map.elevation(r, c), sigma = map.sigma(r, c);
  const bool first = s_.withHeight() == 0;
  s_.min_z = first ? z : std::min(s_.min_z, z);
  s_.max_z = first ? z : std::max(s_.max_z, z);
  ++(map.isKnown(r, c) ? s_.known : s_.oblique);
  sum_z_ += z;
  sum_var_ += sigma * sigma;
}

RegionSummary RegionAccumulator::result() const {
  RegionSummary s = s_;
  if (const int n = s.withHeight(); n > 0) {
    s.mean_z = sum_z_ / n;
    s.mean_sigma = std::sqrt(sum_var_) / n;
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
        if (hasHeight(e.state))
          out.setHeight(r, c, e.state, e.z, e.sigma);
        else
          out.setUnobserved(r, c, e.state);
      } else if (s.withHeight() > 0) {
        out.setHeight(r, c, s.known > 0 ? CellState::kKnown : CellState::kOblique, s.mean_z,
                      s.mean_sigma, float(s.withHeight()));
      } else {
        out.setUnobserved(r, c, s.shadow > 0 ? CellState::kShadow : CellState::kUnknown);
      }
    }
  return out;
}

}  // namespace ambler::terrain

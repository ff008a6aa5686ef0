#pragma once

#include <limits>

#include "core/Region.h"
#include "terrain/ElevationMap.h"

namespace ambler::terrain {

// What the planners ask the map (krotkov1989 §5, fig. 8: elevation and
// uncertainty at a point and over a polygonal region).
struct HeightEstimate {
  CellState state = CellState::kUnknown;
  double z = std::numeric_limits<double>::quiet_NaN();      // [m]
  double sigma = std::numeric_limits<double>::quiet_NaN();  // [m]
};

// The cell under (x, y); unknown outside the map.
HeightEstimate heightAt(const ElevationMap& map, double x, double y);

// The cells of a region, counted by state, and the heights of those that
// have one (known and oblique): extremes, mean, and the sigma of that mean
// (independent cells).
struct RegionSummary {
  int known = 0;
  int unknown = 0;
  int shadow = 0;
  int oblique = 0;
  double min_z = std::numeric_limits<double>::quiet_NaN();
  double max_z = std::numeric_limits<double>::quiet_NaN();
  double mean_z = std::numeric_limits<double>::quiet_NaN();
  double mean_sigma = std::numeric_limits<double>::quiet_NaN();
  int cells() const { return known + unknown + shadow + oblique; }
  int withHeight() const { return known + oblique; }
};

class RegionAccumulator {
 public:
  void add(const ElevationMap& map, int r, int c);
  RegionSummary result() const;

 private:
  RegionSummary s_;
  double sum_z_ = 0.0, sum_var_ = 0.0;
};

// For a Box2, Polygon2 or Disk (cells whose centres lie inside).
template <typename Region>
RegionSummary summarize(const ElevationMap& map, const Region& region) {
  RegionAccumulator acc;
  forEachCellIn(map.grid(), region, [&](int r, int c) { acc.add(map, r, c); });
  return acc.result();
}

// The map at another resolution over the same area: each new cell is the
// summary of the source cells whose centres it covers (mean height, sigma
// of the mean); a new cell covering no source centre (finer resolution)
// copies the source cell under its own centre. Known wins over oblique,
// oblique over shadow, shadow over unknown.
ElevationMap resample(const ElevationMap& map, double resolution);

}  // namespace ambler::terrain

#pragma once

#include "core/GridSpec.h"
#include "sensor/RangeImage.h"
#include "terrain/ElevationMap.h"

namespace ambler::terrain {

// The Cartesian baseline krotkov1989 §3 argues against: eq. 1 applied to
// every pixel, and each cell the mean height of the points that fall in it.
// A point's height sigma is its range sigma times the vertical component of
// its ray (flat ground); a cell's is that of the mean. Cells without points
// are unknown: binning cannot tell a range shadow from a gap between
// samples.
ElevationMap buildBinnedMap(const sensor::RangeImage& image, const GridSpec& grid);

}  // namespace ambler::terrain

#pragma once

#include "core/GridSpec.h"
#include "io/Image.h"
#include "sensor/RangeImage.h"

namespace ambler::widgets {

// What the views show of one scan: the range image and the ground under
// it as a height grid (from the simulator's terrain or, later, the map).
struct ScanDisplay {
  sensor::RangeImage scan;
  GridSpec ground_grid;
  io::FloatImage ground;  // [m]
  double scan_ms = 0.0;   // time the scan took to produce
};

}  // namespace ambler::widgets

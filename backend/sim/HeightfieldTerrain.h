#pragma once

#include <filesystem>

#include "io/Dtm.h"
#include "io/Image.h"
#include "sim/Terrain.h"

namespace ambler::sim {

// Terrain from a sampled heightfield: sample (r, c) is the height at the
// centre of grid cell (r, c) (GridSpec convention), bilinear in between.
// NaN samples are holes; the extent runs from the first to the last centre.
class HeightfieldTerrain : public Terrain {
 public:
  HeightfieldTerrain(io::FloatImage heights, const GridSpec& grid);

  double height(double x, double y) const override;
  double maxHeightIn(const Box2& box) const override;
  Box2 extent() const override;

  const GridSpec& grid() const { return grid_; }

 private:
  io::FloatImage heights_;
  GridSpec grid_;
};

// Loads a float32 TIFF heightfield [m] with a JSON sidecar of the same
// basename: {"origin_x", "origin_y", "resolution"} (docs/formats.md).
// Throws io::FormatError.
HeightfieldTerrain loadHeightfield(const std::filesystem::path& tiff_path);

// A window of a real terrain model (io::readDtm: GeoTIFF, PDS3/PDS4,
// ISIS3, ...) in a frame with its origin at the window's centre, x east,
// y north. Throws io::FormatError.
struct DtmSource {
  std::filesystem::path path;
  io::DtmWindow window;
};
HeightfieldTerrain loadDtm(const DtmSource& source);

}  // namespace ambler::sim

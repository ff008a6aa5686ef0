#include "sim/HeightfieldTerrain.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/Json.h"
#include "io/Tiff.h"

namespace ambler::sim {

HeightfieldTerrain::HeightfieldTerrain(io::FloatImage heights, const GridSpec& grid)
    : heights_(std::move(heights)), grid_(grid) {
  grid_.rows = heights_.rows;
  grid_.cols = heights_.cols;
}

Box2 HeightfieldTerrain::extent() const {
  const auto first = grid_.cellCenter(0, 0);
  const auto last = grid_.cellCenter(grid_.rows - 1, grid_.cols - 1);
  return {first.x(), first.y(), last.x(), last.y()};
}

double HeightfieldTerrain::height(double x, double y) const {
  if (!extent().contains(x, y)) return std::numeric_limits<double>::quiet_NaN();
  const double u = (x - grid_.origin_x) / grid_.resolution - 0.5;
  const double v = (y - grid_.origin_y) / grid_.resolution - 0.5;
  const int c0 = std::min(int(u), grid_.cols - 2 < 0 ? 0 : grid_.cols - 2);
  const int r0 = std::min(int(v), grid_.rows - 2 < 0 ? 0 : grid_.rows - 2);
  const int c1 = std::min(c0 + 1, grid_.cols - 1), r1 = std::min(r0 + 1, grid_.rows - 1);
  const double fu = u - c0, fv = v - r0;
  return (1 - fv) * ((1 - fu) * heights_(r0, c0) + fu * heights_(r0, c1)) +
         fv * ((1 - fu) * heights_(r1, c0) + fu * heights_(r1, c1));
}

double HeightfieldTerrain::maxHeightIn(const Box2& box) const {
  // Bilinear interpolation never exceeds the samples around it.
  auto index = [&](double value, double origin, int count) {
    return std::clamp(int(std::floor((value - origin) / grid_.resolution - 0.5)), 0, count - 1);
  };
  const int c0 = index(box.x_min, grid_.origin_x, grid_.cols);
  const int c1 = std::min(index(box.x_max, grid_.origin_x, grid_.cols) + 1, grid_.cols - 1);
  const int r0 = index(box.y_min, grid_.origin_y, grid_.rows);
  const int r1 = std::min(index(box.y_max, grid_.origin_y, grid_.rows) + 1, grid_.rows - 1);
  double bound = -std::numeric_limits<double>::infinity();
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      if (std::isfinite(heights_(r, c))) bound = std::max(bound, double(heights_(r, c)));
  return bound;
}

HeightfieldTerrain loadHeightfield(const std::filesystem::path& tiff_path) {
  auto json_path = tiff_path;
  json_path.replace_extension(".json");
  const auto json = io::readJsonFile(json_path);
  const io::JsonFields f(json, "heightfield sidecar '" + json_path.string() + "'");
  const GridSpec grid = io::readGridPlacement(f);
  auto heights = io::readFloatTiff(tiff_path);
  if (heights.rows < 2 || heights.cols < 2)
    throw io::FormatError("heightfield '" + tiff_path.string() + "' needs at least 2x2 samples");
  return HeightfieldTerrain(std::move(heights), grid);
}

HeightfieldTerrain loadDtm(const DtmSource& source) {
  auto dtm = io::readDtm(source.path, source.window);
  return HeightfieldTerrain(std::move(dtm.heights), dtm.grid);
}

}  // namespace ambler::sim

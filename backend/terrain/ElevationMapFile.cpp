#include "terrain/ElevationMapFile.h"

#include <cmath>

#include "io/Dtm.h"
#include "io/Json.h"
#include "io/Tiff.h"

namespace ambler::terrain {

namespace fs = std::filesystem;

namespace {

void requireMapSize(const io::FloatImage& image, const GridSpec& g, const fs::path& path) {
  io::requireSize(image, g.rows, g.cols, path, "map.json");
}

}  // namespace

void writeLayer(const Layer& layer, const GridSpec& grid, const fs::path& file,
                const std::string& unit) {
  io::FloatImage image(int(layer.rows()), int(layer.cols()));
  std::copy(layer.data(), layer.data() + layer.size(), image.pixels.begin());
  io::writeGeoTiff(file, image, grid, unit);
}

void writeElevationMap(const ElevationMap& map, const fs::path& dir) {
  fs::create_directories(dir);
  const auto& g = map.grid();
  writeLayer(map.layer(layer::kElevation), g, dir / "elevation.tif", "m");
  writeLayer(map.layer(layer::kSigma), g, dir / "sigma.tif", "m");
  writeLayer(map.layer(layer::kCount), g, dir / "count.tif");
  io::ByteImage state(g.rows, g.cols);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) state(r, c) = std::uint8_t(map.state(r, c));
  io::writeGeoTiff(dir / "state.tif", state, g);
  auto header = io::gridJson(g);
  header["frame"] = map.frame();
  header["state_codes"] = {{"0", "known"}, {"1", "unknown"}, {"2", "shadow"}, {"3", "oblique"}};
  io::writeJsonFile(dir / "map.json", header);
}

ElevationMap readElevationMap(const fs::path& dir) {
  const fs::path header = dir / "map.json";
  const auto json = io::readJsonFile(header);
  const io::JsonFields f(json, "map header '" + header.string() + "'");
  GridSpec g = io::readGridPlacement(f);
  g.rows = f.integer("rows");
  g.cols = f.integer("cols");
  if (g.rows <= 0 || g.cols <= 0 || double(g.rows) * g.cols > double(io::kMaxTiffPixels))
    f.fail("rows", "and cols must be positive and describe at most 2^28 cells");
  ElevationMap map(g, f.string("frame"));

  const auto elevation = io::readFloatTiff(dir / "elevation.tif");
  requireMapSize(elevation, g, dir / "elevation.tif");
  const auto sigma = io::readFloatTiff(dir / "sigma.tif");
  requireMapSize(sigma, g, dir / "sigma.tif");
  const auto state = io::readByteTiff(dir / "state.tif");
  io::requireSize(state, g.rows, g.cols, dir / "state.tif", "map.json");
  io::FloatImage count(g.rows, g.cols, 1.0f);
  if (fs::exists(dir / "count.tif")) {
    count = io::readFloatTiff(dir / "count.tif");
    requireMapSize(count, g, dir / "count.tif");
  }
  auto cellError = [&](const std::string& file, int r, int c, const std::string& problem) {
    return io::FormatError("'" + (dir / file).string() + "': cell (" + std::to_string(r) + ", " +
                           std::to_string(c) + ") " + problem);
  };
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int code = state(r, c);
      if (code > int(CellState::kOblique))
        throw cellError("state.tif", r, c, "has unknown state code " + std::to_string(code));
      const auto s = CellState(code);
      if (!hasHeight(s)) {
        map.setUnobserved(r, c, s);
        continue;
      }
      const std::string is = s == CellState::kKnown ? "is known" : "is oblique";
      if (!std::isfinite(elevation(r, c)))
        throw cellError("elevation.tif", r, c, is + " but its elevation is not finite");
      if (!std::isfinite(sigma(r, c)) || sigma(r, c) < 0)
        throw cellError("sigma.tif", r, c, is + " but its sigma is not a finite number >= 0");
      map.setHeight(r, c, s, elevation(r, c), sigma(r, c), count(r, c));
    }
  return map;
}

}  // namespace ambler::terrain

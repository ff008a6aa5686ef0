#pragma once

#include <filesystem>

#include "terrain/ElevationMap.h"

namespace ambler::terrain {

// An elevation map as a folder (docs/formats.md): elevation.tif, sigma.tif
// (float32, NaN unless known), state.tif (uint8 CellState codes),
// count.tif (float32) and map.json with the grid and frame. map.json is
// written last, so a folder with it is complete. The layers are GeoTIFFs
// (geotransform of the map's frame, NaN no-data), so GIS tools place them.
void writeElevationMap(const ElevationMap& map, const std::filesystem::path& dir);

// One layer on `grid` as a float32 GeoTIFF, written atomically
// (io::writeGeoTiff); `unit` of its values, empty for none.
void writeLayer(const Layer& layer, const GridSpec& grid, const std::filesystem::path& file,
                const std::string& unit = {});

// Throws io::FormatError naming the file and the problem: missing or
// malformed header, layer of the wrong size, unknown state code, a known
// cell without a finite height and non-negative sigma.
ElevationMap readElevationMap(const std::filesystem::path& dir);

}  // namespace ambler::terrain

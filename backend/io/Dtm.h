#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>

#include "core/GridSpec.h"
#include "io/Image.h"

namespace ambler::io {

// The part of a digital terrain model to load, on the simulator's grid.
struct DtmWindow {
  // In the DTM's projected coordinates [m]; default: the raster's centre.
  std::optional<Eigen::Vector2d> centre{};
  double width = 0.0;       // east-west [m]; 0: the whole raster
  double height = 0.0;      // north-south [m]; 0: the whole raster
  double resolution = 0.0;  // cell size [m]; 0: the DTM's own pixel size
};

// A window of a DTM resampled to a grid whose frame has x east, y north
// (metres) and its origin at the window's centre; heights in metres of the
// DTM's own datum, NaN where it has no data.
struct Dtm {
  FloatImage heights;  // GridSpec convention: row 0 is the southern edge
  GridSpec grid;
  Eigen::Vector2d centre{0.0, 0.0};  // the frame's origin in DTM coordinates [m]
  std::string driver;                // GDAL's name of the format read
};

// Reads any DTM GDAL reads: GeoTIFF, PDS3, PDS4 and ISIS3 cubes (the
// formats of HiRISE and CTX DTMs), among others. Honours the band's
// no-data value, scale and offset, its unit (m, km, ft) and the CRS's
// linear unit; heights beyond 1e9 m are undeclared no-data markers
// (ISIS3's special pixels besides NULL). Resampling is bilinear, or the
// mean of the source pixels in a cell when the cell is over 1.5 source
// pixels wide; a cell touching no-data has none. Throws FormatError naming
// the file and the problem: not a raster, rotated or geographic (degrees)
// coordinates, an unknown height unit, a window off the raster, too large
// or holding no heights at all, a non-positive resolution.
Dtm readDtm(const std::filesystem::path& path, const DtmWindow& window = {});

// A GeoTIFF of `image` on `grid` (GridSpec convention, so the
// geotransform's row step is positive): float32 with NaN as no-data, or
// uint8 codes without one; `unit` names the values' unit (empty: none).
// Written to a temporary file and renamed, so a reader never sees half a
// file; the project's TIFF readers read it as before. Throws FormatError
// when it cannot write.
void writeGeoTiff(const std::filesystem::path& path, const FloatImage& image, const GridSpec& grid,
                  const std::string& unit = {});
void writeGeoTiff(const std::filesystem::path& path, const ByteImage& image, const GridSpec& grid);

}  // namespace ambler::io

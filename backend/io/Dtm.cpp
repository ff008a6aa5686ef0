#include "io/Dtm.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include "io/FormatError.h"
#include "io/ReplaceFile.h"

namespace ambler::io {

namespace {

// Caps what one load may allocate: 2^28 cells, as for TIFFs.
constexpr double kMaxCells = double(1L << 28);

// Heights beyond this are no-data markers the band does not declare: ISIS3's
// special pixels other than NULL (LRS, LIS, HIS, HRS, all near -3.4e38),
// which GDAL leaves as values, and the float extremes other tools use. No
// body's radius comes near it.
constexpr double kImplausibleHeightM = 1e9;

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

void registerDrivers() {
  static std::once_flag once;
  std::call_once(once, [] {
    GDALAllRegister();
    // Errors come back through return values and become FormatError; the
    // default handler would also print them to stderr.
    CPLSetErrorHandler(CPLQuietErrorHandler);
  });
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw FormatError(path.string() + ": " + why);
}

// Metres per unit of the band's values.
double heightUnit(const std::filesystem::path& path, std::string unit) {
  std::transform(unit.begin(), unit.end(), unit.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (unit.empty() || unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" ||
      unit == "meters")
    return 1.0;
  if (unit == "km" || unit == "kilometre" || unit == "kilometer" || unit == "kilometers")
    return 1000.0;
  if (unit == "ft" || unit == "foot" || unit == "feet") return 0.3048;
  if (unit == "us-ft" || unit == "us survey foot") return 1200.0 / 3937.0;
  fail(path, "unknown height unit '" + unit + "' (expected m, km or ft)");
}

// Metres per unit of the horizontal coordinates; no CRS means metres.
double horizontalUnit(const std::filesystem::path& path, const OGRSpatialReference* srs) {
  if (!srs || srs->IsEmpty()) return 1.0;
  if (srs->IsGeographic())
    fail(path,
         "coordinates are geographic (degrees); reproject the DTM to a projected CRS in "
         "metres first (e.g. gdalwarp -t_srs with an equirectangular or polar stereographic "
         "projection)");
  return srs->GetLinearUnits();
}

// The source raster, in metres, with NaN for no-data: source pixel (i, j)
// has its centre at (x0 + (j + 0.5) dx, y0 + (i + 0.5) dy).
struct Source {
  std::vector<float> z;
  int rows = 0, cols = 0;
  double x0 = 0, y0 = 0, dx = 1, dy = -1;

  double at(int i, int j) const { return z[std::size_t(i) * cols + j]; }
};

double bilinear(const Source& s, double x, double y) {
  const double u = (x - s.x0) / s.dx - 0.5, v = (y - s.y0) / s.dy - 0.5;
  const int j = int(std::floor(u)), i = int(std::floor(v));
  if (i < 0 || j < 0 || i + 1 >= s.rows || j + 1 >= s.cols) {
    // On the raster's outer half pixel: the nearest sample.
    const int ni = int(std::lround(v)), nj = int(std::lround(u));
    if (ni < 0 || nj < 0 || ni >= s.rows || nj >= s.cols) return NAN;
    return s.at(ni, nj);
  }
  const double fu = u - j, fv = v - i;
  return (1 - fv) * ((1 - fu) * s.at(i, j) + fu * s.at(i, j + 1)) +
         fv * ((1 - fu) * s.at(i + 1, j) + fu * s.at(i + 1, j + 1));
}

// The mean of the source pixels whose centres fall in the cell.
double cellMean(const Source& s, double x_lo, double y_lo, double size) {
  const double u0 = (x_lo - s.x0) / s.dx - 0.5, u1 = (x_lo + size - s.x0) / s.dx - 0.5;
  const double v0 = (y_lo - s.y0) / s.dy - 0.5, v1 = (y_lo + size - s.y0) / s.dy - 0.5;
  const int j0 = std::max(0, int(std::ceil(std::min(u0, u1))));
  const int j1 = std::min(s.cols - 1, int(std::floor(std::max(u0, u1))));
  const int i0 = std::max(0, int(std::ceil(std::min(v0, v1))));
  const int i1 = std::min(s.rows - 1, int(std::floor(std::max(v0, v1))));
  double sum = 0.0;
  int n = 0;
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j, ++n) sum += s.at(i, j);
  return n ? sum / n : NAN;
}

// A north-up raster's pixel grid in metres: pixel (i, j) spans
// [x0 + j dx, x0 + (j + 1) dx] x [y0 + i dy, y0 + (i + 1) dy].
struct RasterGrid {
  int rows = 0, cols = 0;
  double x0 = 0, y0 = 0, dx = 1, dy = -1;

  Box2 extent() const {
    return {std::min(x0, x0 + cols * dx), std::min(y0, y0 + rows * dy),
            std::max(x0, x0 + cols * dx), std::max(y0, y0 + rows * dy)};
  }
};

RasterGrid rasterGrid(const std::filesystem::path& path, GDALDataset& ds) {
  double gt[6];
  if (ds.GetGeoTransform(gt) != CE_None) fail(path, "has no geotransform (pixel size unknown)");
  if (gt[2] != 0.0 || gt[4] != 0.0) fail(path, "is rotated; only north-up rasters are read");
  if (gt[1] == 0.0 || gt[5] == 0.0) fail(path, "has a zero pixel size");
  const double unit = horizontalUnit(path, ds.GetSpatialRef());
  return {ds.GetRasterYSize(), ds.GetRasterXSize(), gt[0] * unit,
          gt[3] * unit,        gt[1] * unit,        gt[5] * unit};
}

// The part of the raster the window asks for: its centre, size and the
// cell size of the result, defaults filled in from the raster.
struct WantedWindow {
  Eigen::Vector2d centre;
  double width = 0, height = 0, resolution = 0;
  Box2 box() const {
    return {centre.x() - width / 2, centre.y() - height / 2, centre.x() + width / 2,
            centre.y() + height / 2};
  }
};

WantedWindow wantedWindow(const std::filesystem::path& path, const RasterGrid& g,
                          const DtmWindow& window) {
  const Box2 raster = g.extent();
  WantedWindow w;
  w.centre = window.centre.value_or(
      Eigen::Vector2d(0.5 * (raster.x_min + raster.x_max), 0.5 * (raster.y_min + raster.y_max)));
  w.width = window.width > 0 ? window.width : raster.width();
  w.height = window.height > 0 ? window.height : raster.height();
  w.resolution = window.resolution > 0 ? window.resolution : std::abs(g.dx);
  if (!(window.resolution >= 0) || !(window.width >= 0) || !(window.height >= 0) ||
      !std::isfinite(w.centre.x()) || !std::isfinite(w.centre.y()))
    fail(path, "window or resolution is negative or not a number");
  const Box2 wanted = w.box();
  if (wanted.x_max <= raster.x_min || wanted.x_min >= raster.x_max ||
      wanted.y_max <= raster.y_min || wanted.y_min >= raster.y_max)
    fail(path, "the window lies off the raster");
  if (w.width / w.resolution * (w.height / w.resolution) > kMaxCells)
    fail(path, "the window holds over 2^28 cells at this resolution");
  return w;
}

// The source pixels under `wanted`, with one pixel of margin, in metres
// (the band's scale and offset applied, then its unit, `z_unit` metres)
// and NaN for no-data.
Source readSource(const std::filesystem::path& path, GDALRasterBand& band, double z_unit,
                  const RasterGrid& g, const Box2& wanted) {
  int has_scale = 0, has_offset = 0, has_nodata = 0;
  const double scale = band.GetScale(&has_scale), offset = band.GetOffset(&has_offset);
  const double nodata = band.GetNoDataValue(&has_nodata);
  auto col = [&](double x) { return (x - g.x0) / g.dx; };
  auto row = [&](double y) { return (y - g.y0) / g.dy; };
  const int j0 = std::clamp(int(std::floor(std::min(col(wanted.x_min), col(wanted.x_max)))) - 1, 0,
                            g.cols - 1);
  const int j1 =
      std::clamp(int(std::ceil(std::max(col(wanted.x_min), col(wanted.x_max)))) + 1, 0, g.cols - 1);
  const int i0 = std::clamp(int(std::floor(std::min(row(wanted.y_min), row(wanted.y_max)))) - 1, 0,
                            g.rows - 1);
  const int i1 =
      std::clamp(int(std::ceil(std::max(row(wanted.y_min), row(wanted.y_max)))) + 1, 0, g.rows - 1);
  Source s;
  s.cols = j1 - j0 + 1;
  s.rows = i1 - i0 + 1;
  if (double(s.cols) * s.rows > kMaxCells) fail(path, "the window covers over 2^28 DTM pixels");
  s.dx = g.dx;
  s.dy = g.dy;
  s.x0 = g.x0 + j0 * g.dx;
  s.y0 = g.y0 + i0 * g.dy;
  std::vector<double> raw(std::size_t(s.cols) * s.rows);
  if (band.RasterIO(GF_Read, j0, i0, s.cols, s.rows, raw.data(), s.cols, s.rows, GDT_Float64, 0,
                    0) != CE_None)
    fail(path, std::string("cannot read its pixels: ") + CPLGetLastErrorMsg());
  s.z.resize(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const double metres =
        ((has_scale ? scale : 1.0) * raw[k] + (has_offset ? offset : 0.0)) * z_unit;
    // NaN, declared or not, fails the second test.
    const bool missing =
        (has_nodata && raw[k] == nodata) || !(std::abs(metres) < kImplausibleHeightM);
    s.z[k] = missing ? NAN : float(metres);
  }
  return s;
}

}  // namespace

Dtm readDtm(const std::filesystem::path& path, const DtmWindow& window) {
  registerDrivers();
  Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) fail(path, std::string("not a raster GDAL can read: ") + CPLGetLastErrorMsg());
  if (ds->GetRasterCount() < 1) fail(path, "has no raster band");
  const RasterGrid raster = rasterGrid(path, *ds);
  auto& band = *ds->GetRasterBand(1);
  const double z_unit = heightUnit(path, band.GetUnitType());
  const WantedWindow w = wantedWindow(path, raster, window);
  const Source s = readSource(path, band, z_unit, raster, w.box());

  Dtm dtm;
  dtm.driver = ds->GetDriverName();
  dtm.centre = w.centre;
  const double res = w.resolution;
  dtm.grid.resolution = res;
  dtm.grid.cols = std::max(1, int(std::floor(w.width / res + 1e-9)));
  dtm.grid.rows = std::max(1, int(std::floor(w.height / res + 1e-9)));
  dtm.grid.origin_x = -0.5 * dtm.grid.cols * res;
  dtm.grid.origin_y = -0.5 * dtm.grid.rows * res;
  dtm.heights = FloatImage(dtm.grid.rows, dtm.grid.cols);
  const bool average = res > 1.5 * std::abs(s.dx) || res > 1.5 * std::abs(s.dy);
  for (int r = 0; r < dtm.grid.rows; ++r)
    for (int c = 0; c < dtm.grid.cols; ++c) {
      const Eigen::Vector2d p = dtm.grid.cellCenter(r, c) + w.centre;
      dtm.heights(r, c) = float(average ? cellMean(s, p.x() - res / 2, p.y() - res / 2, res)
                                        : bilinear(s, p.x(), p.y()));
    }
  if (std::none_of(dtm.heights.pixels.begin(), dtm.heights.pixels.end(),
                   [](float z) { return std::isfinite(z); }))
    fail(path, "has no heights in the window (all no-data)");
  return dtm;
}

namespace {

template <typename T>
void writeGeoTiffAs(const std::filesystem::path& path, const Image<T>& image, const GridSpec& grid,
                    GDALDataType type, const std::string& unit, bool nan_is_nodata) {
  registerDrivers();
  auto* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) fail(path, "GDAL has no GeoTIFF driver");
  if (image.rows != grid.rows || image.cols != grid.cols)
    fail(path, "the raster is not the size of its grid");
  writeThenReplace(path, [&](const std::filesystem::path& partial) {
    Dataset ds(driver->Create(partial.c_str(), image.cols, image.rows, 1, type, nullptr));
    if (!ds) fail(path, std::string("cannot create: ") + CPLGetLastErrorMsg());
    double gt[6] = {grid.origin_x, grid.resolution, 0.0, grid.origin_y, 0.0, grid.resolution};
    ds->SetGeoTransform(gt);
    auto* band = ds->GetRasterBand(1);
    if (nan_is_nodata) band->SetNoDataValue(NAN);
    if (!unit.empty()) band->SetUnitType(unit.c_str());
    // RasterIO takes a non-const buffer but only reads it when writing.
    auto* pixels = const_cast<T*>(image.pixels.data());
    if (band->RasterIO(GF_Write, 0, 0, image.cols, image.rows, pixels, image.cols, image.rows, type,
                       0, 0) != CE_None)
      fail(path, std::string("cannot write: ") + CPLGetLastErrorMsg());
  });
}

}  // namespace

void writeGeoTiff(const std::filesystem::path& path, const FloatImage& image, const GridSpec& grid,
                  const std::string& unit) {
  writeGeoTiffAs(path, image, grid, GDT_Float32, unit, true);
}

void writeGeoTiff(const std::filesystem::path& path, const ByteImage& image, const GridSpec& grid) {
  writeGeoTiffAs(path, image, grid, GDT_Byte, {}, false);
}

}  // namespace ambler::io

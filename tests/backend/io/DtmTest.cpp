#include "io/Dtm.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "TempDir.h"
#include "io/FormatError.h"
#include "io/Tiff.h"

namespace ambler::io {
namespace {

// An equirectangular Mars projection in metres, as HiRISE DTMs use.
std::string marsWkt() {
  OGRSpatialReference srs;
  srs.SetGeogCS("Mars 2000", "D_Mars_2000", "Mars_2000_IAU_IAG", 3396190.0, 169.894447223612);
  srs.SetEquirectangular2(0.0, 0.0, 0.0, 0.0, 0.0);
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  std::string out(wkt);
  CPLFree(wkt);
  return out;
}

// The plane z = 2 + 0.01 e + 0.02 n [m] (e, n: easting and northing in
// metres from the raster's north-west corner at (1000, 5000)), 1 m pixels,
// stored as (z - offset) / scale in `unit`, with a no-data square.
struct Sample {
  static constexpr double kNoData = -32768.0;
};

double plane(double e, double n) { return 2.0 + 0.01 * (e - 1000.0) + 0.02 * (n - 5000.0); }

std::filesystem::path writeSample(const std::filesystem::path& dir, const char* driver_name,
                                  const char* ext, const std::string& wkt, const char* unit,
                                  double unit_m, double scale, double offset) {
  GDALAllRegister();
  const int cols = 120, rows = 80;
  auto* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDataset* ds = mem->Create("", cols, rows, 1, GDT_Float32, nullptr);
  double gt[6] = {1000.0, 1.0, 0.0, 5000.0 + rows, 0.0, -1.0};  // north-up
  ds->SetGeoTransform(gt);
  if (!wkt.empty()) ds->SetProjection(wkt.c_str());
  auto* band = ds->GetRasterBand(1);
  std::vector<float> z(std::size_t(cols) * rows);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double e = 1000.0 + j + 0.5, n = 5000.0 + rows - i - 0.5;
      const bool hole = j >= 10 && j < 20 && i >= 10 && i < 20;
      z[std::size_t(i) * cols + j] =
          hole ? float(Sample::kNoData) : float((plane(e, n) / unit_m - offset) / scale);
    }
  EXPECT_EQ(band->RasterIO(GF_Write, 0, 0, cols, rows, z.data(), cols, rows, GDT_Float32, 0, 0),
            CE_None);
  band->SetNoDataValue(Sample::kNoData);
  band->SetScale(scale);
  band->SetOffset(offset);
  band->SetUnitType(unit);
  const auto path = dir / (std::string("dtm.") + ext);
  auto* driver = GetGDALDriverManager()->GetDriverByName(driver_name);
  GDALDataset* out = driver->CreateCopy(path.c_str(), ds, FALSE, nullptr, nullptr, nullptr);
  EXPECT_NE(out, nullptr) << driver_name << ": " << CPLGetLastErrorMsg();
  GDALClose(out);
  GDALClose(ds);
  return path;
}

struct Format {
  const char* driver;
  const char* ext;
  const char* unit;
  double unit_m, scale, offset;
};

void PrintTo(const Format& f, std::ostream* os) { *os << f.driver << " in " << f.unit; }

class DtmFormats : public ::testing::TestWithParam<Format> {};

// HiRISE and CTX DTMs come as GeoTIFF, PDS4 and ISIS3 cubes: each loads to
// the same heights, cropped and resampled, with units, scale and offset
// honoured and no-data left out.
TEST_P(DtmFormats, LoadsAPlaneCroppedAndResampled) {
  const auto f = GetParam();
  TempDir dir;
  const auto path =
      writeSample(dir.path(), f.driver, f.ext, marsWkt(), f.unit, f.unit_m, f.scale, f.offset);
  // A 40 x 30 m window at 0.25 m (bilinear) and at 2 m (cell means).
  for (const double res : {0.25, 2.0}) {
    const auto dtm = readDtm(path, {.centre = Eigen::Vector2d(1060.0, 5040.0),
                                    .width = 40.0,
                                    .height = 30.0,
                                    .resolution = res});
    EXPECT_EQ(dtm.grid.cols, int(40 / res));
    EXPECT_EQ(dtm.grid.rows, int(30 / res));
    for (int r = 0; r < dtm.grid.rows; ++r)
      for (int c = 0; c < dtm.grid.cols; ++c) {
        const Eigen::Vector2d p = dtm.grid.cellCenter(r, c) + dtm.centre;
        ASSERT_NEAR(dtm.heights(r, c), plane(p.x(), p.y()), 2e-3)
            << f.driver << " res " << res << " at " << p.transpose();
      }
  }
  // The no-data square (easting 1010-1020, northing 5060-5070) has no height.
  const auto whole = readDtm(path);
  EXPECT_EQ(whole.grid.cols, 120);
  EXPECT_EQ(whole.grid.rows, 80);
  const auto inHole = whole.grid.cellAt(1015.0 - whole.centre.x(), 5065.0 - whole.centre.y());
  ASSERT_TRUE(inHole);
  EXPECT_TRUE(std::isnan(whole.heights(inHole->row, inHole->col))) << f.driver;
  EXPECT_NEAR(whole.heights(0, 0), plane(1000.5, 5000.5), 2e-3);  // row 0 is the south
}

INSTANTIATE_TEST_SUITE_P(Dtm, DtmFormats,
                         ::testing::Values(Format{"GTiff", "tif", "m", 1.0, 1.0, 0.0},
                                           Format{"GTiff", "tif", "km", 1000.0, 0.001, -3.0},
                                           Format{"PDS4", "xml", "m", 1.0, 0.5, 100.0},
                                           Format{"ISIS3", "cub", "m", 1.0, 1.0, 0.0}),
                         [](const auto& info) {
                           return std::string(info.param.driver) + "_" + info.param.unit;
                         });

TEST(Dtm, RefusesWhatItCannotPlaceWithAReason) {
  TempDir dir;
  auto expectError = [](const std::filesystem::path& p, const DtmWindow& w, const char* words) {
    try {
      (void)readDtm(p, w);
      ADD_FAILURE() << "no error for " << p;
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  // Geographic coordinates are degrees, not metres.
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  char* wkt = nullptr;
  wgs84.exportToWkt(&wkt);
  const auto geographic = writeSample(dir.path(), "GTiff", "tif", wkt, "m", 1.0, 1.0, 0.0);
  CPLFree(wkt);
  expectError(geographic, {}, "degrees");
  const auto odd_unit =
      writeSample(dir.path(), "GTiff", "tif", marsWkt(), "furlong", 1.0, 1.0, 0.0);
  expectError(odd_unit, {}, "furlong");
  const auto metres = writeSample(dir.path(), "ISIS3", "cub", marsWkt(), "m", 1.0, 1.0, 0.0);
  expectError(metres, {.centre = Eigen::Vector2d(0.0, 0.0), .width = 10, .height = 10},
              "off the raster");
  expectError(metres, {.resolution = -1.0}, "negative");
  expectError(metres, {.width = 1e6, .height = 1e6, .resolution = 0.01}, "2^28");
  // Not a raster at all, and a truncated one.
  std::ofstream(dir / "junk.tif") << "not a tiff";
  expectError(dir / "junk.tif", {}, "not a raster");
  expectError(dir / "missing.tif", {}, "not a raster");
}

// ISIS3 cubes mark more than NULL: the low and high representation and
// instrument saturation pixels (LRS, LIS, HIS, HRS) are floats near
// -3.4e38 that GDAL does not declare as no-data. Read as heights, one put a
// simulated scanner 3.4e38 m below the ground. A window with no heights at
// all is refused.
TEST(Dtm, UndeclaredMarkersAreNoDataAndAnEmptyWindowIsRefused) {
  TempDir dir;
  GDALAllRegister();
  const int cols = 40, rows = 30;
  auto* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDataset* ds = mem->Create("", cols, rows, 1, GDT_Float32, nullptr);
  double gt[6] = {1000.0, 1.0, 0.0, 5000.0 + rows, 0.0, -1.0};
  ds->SetGeoTransform(gt);
  ds->SetProjection(marsWkt().c_str());
  const std::uint32_t markers[] = {0xFF7FFFFCu, 0xFF7FFFFDu, 0xFF7FFFFEu, 0xFF7FFFFFu};
  std::vector<float> z(std::size_t(cols) * rows, 7.0f);
  for (int k = 0; k < 4; ++k) std::memcpy(&z[std::size_t(5) * cols + 5 + 10 * k], &markers[k], 4);
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, cols, rows, z.data(), cols, rows,
                                           GDT_Float32, 0, 0),
            CE_None);
  auto* isis = GetGDALDriverManager()->GetDriverByName("ISIS3");
  GDALClose(isis->CreateCopy((dir / "special.cub").c_str(), ds, FALSE, nullptr, nullptr, nullptr));
  GDALClose(ds);

  // The markers at raster row 5, columns 5, 15, 25 and 35: each cell at
  // such a pixel has no height, and every cell that has one is the ground's
  // (bilinear resampling may take no-data up to a pixel away).
  const auto dtm = readDtm(dir / "special.cub");
  auto nearMarker = [](const Eigen::Vector2d& p) {
    const double col = p.x() - 1000.0 - 0.5, row = 5000.0 + rows - p.y() - 0.5;
    const double to_marker = std::abs(col - 5.0 - 10.0 * std::round((col - 5.0) / 10.0));
    return std::abs(row - 5.0) <= 1.0 && to_marker <= 1.0 && col >= 4.0 && col <= 36.0;
  };
  int missing = 0;
  for (int r = 0; r < dtm.grid.rows; ++r)
    for (int c = 0; c < dtm.grid.cols; ++c) {
      const Eigen::Vector2d p = dtm.grid.cellCenter(r, c) + dtm.centre;
      if (std::isnan(dtm.heights(r, c))) {
        ++missing;
        EXPECT_TRUE(nearMarker(p)) << p.transpose();
      } else {
        EXPECT_FLOAT_EQ(dtm.heights(r, c), 7.0f) << p.transpose();
      }
    }
  EXPECT_GE(missing, 4);
  for (int k = 0; k < 4; ++k) {
    const auto cell = dtm.grid.cellAt(1005.5 + 10 * k - dtm.centre.x(), 5024.5 - dtm.centre.y());
    ASSERT_TRUE(cell);
    EXPECT_TRUE(std::isnan(dtm.heights(cell->row, cell->col))) << "marker " << k;
  }

  // The no-data square of writeSample (easting 1010-1020, northing
  // 5060-5070) holds no height.
  const auto holed = writeSample(dir.path(), "GTiff", "tif", marsWkt(), "m", 1.0, 1.0, 0.0);
  try {
    (void)readDtm(holed, {.centre = Eigen::Vector2d(1015.0, 5065.0), .width = 6, .height = 6});
    ADD_FAILURE() << "a window of no-data was read";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("no heights in the window"), std::string::npos)
        << e.what();
  }
}

// Map layers written as GeoTIFF carry the grid as a geotransform, NaN as
// no-data, and still read with the project's own TIFF reader.
TEST(Dtm, GeoTiffLayersRoundTrip) {
  TempDir dir;
  GridSpec grid{-2.0, 3.0, 0.5, 4, 6};
  FloatImage z(4, 6, 1.5f);
  z(1, 2) = NAN;
  writeGeoTiff(dir / "z.tif", z, grid, "m");
  EXPECT_FALSE(std::filesystem::exists(dir / "z.tif.partial"));
  const auto back = readFloatTiff(dir / "z.tif");
  EXPECT_EQ(back.rows, 4);
  EXPECT_TRUE(std::isnan(back(1, 2)));
  EXPECT_EQ(back(3, 5), 1.5f);
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open((dir / "z.tif").c_str(), GDAL_OF_RASTER);
  ASSERT_NE(ds, nullptr);
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  EXPECT_EQ(gt[0], -2.0);
  EXPECT_EQ(gt[3], 3.0);
  EXPECT_EQ(gt[1], 0.5);
  EXPECT_EQ(gt[5], 0.5);  // row 0 at the grid's lower edge
  int has = 0;
  EXPECT_TRUE(std::isnan(ds->GetRasterBand(1)->GetNoDataValue(&has)));
  EXPECT_TRUE(has);
  EXPECT_STREQ(ds->GetRasterBand(1)->GetUnitType(), "m");
  GDALClose(ds);
  // Its own reader places the raster where it was written.
  const auto dtm = readDtm(dir / "z.tif");
  EXPECT_NEAR(dtm.centre.x(), -0.5, 1e-12);
  EXPECT_NEAR(dtm.centre.y(), 4.0, 1e-12);
  EXPECT_EQ(dtm.heights(3, 5), 1.5f);
  EXPECT_TRUE(std::isnan(dtm.heights(1, 2)));
}

}  // namespace
}  // namespace ambler::io

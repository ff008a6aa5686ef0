#include "terrain/ElevationMap.h"

#include <gtest/gtest.h>

#include <fstream>

#include "TempDir.h"
#include "io/FormatError.h"
#include "io/Tiff.h"
#include "terrain/ElevationMapFile.h"
#include "terrain/Queries.h"

namespace ambler::terrain {
namespace {

// 4 x 4 cells of 1 m from (0, 0); heights r + c, sigma 0.1 except the
// corner cell (3, 3), which is shadow.
ElevationMap rampMap() {
  ElevationMap map(GridSpec::covering({0, 0, 4, 4}, 1.0));
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) map.setKnown(r, c, r + c, 0.1);
  map.setUnobserved(3, 3, CellState::kShadow);
  return map;
}

TEST(ElevationMap, StartsUnknownWithTheFourNamedLayers) {
  const ElevationMap map(GridSpec::covering({0, 0, 2, 3}, 0.5), "rover");
  EXPECT_EQ(map.frame(), "rover");
  EXPECT_EQ(map.layerNames(), (std::vector<std::string>{"elevation", "sigma", "state", "count"}));
  EXPECT_EQ(map.countOf(CellState::kUnknown), 24);
  EXPECT_TRUE(std::isnan(map.elevation(0, 0)));
  EXPECT_EQ(map.layer(layer::kCount).sum(), 0.0f);
  EXPECT_THROW(map.layer("roughness"), std::out_of_range);
}

TEST(ElevationMap, ExtraLayersHaveTheGridsSize) {
  ElevationMap map(GridSpec::covering({0, 0, 2, 3}, 0.5));
  auto& cost = map.addLayer("cost", 1.5f);
  EXPECT_EQ(cost.rows(), 6);
  EXPECT_EQ(cost.cols(), 4);
  EXPECT_TRUE(map.hasLayer("cost"));
  EXPECT_FLOAT_EQ(map.layer("cost")(5, 3), 1.5f);
}

TEST(Queries, HeightAtAPointIsTheCellUnderIt) {
  const auto map = rampMap();
  const auto e = heightAt(map, 2.5, 1.5);  // column 2, row 1
  EXPECT_EQ(e.state, CellState::kKnown);
  EXPECT_DOUBLE_EQ(e.z, 3.0);
  EXPECT_FLOAT_EQ(float(e.sigma), 0.1f);
  EXPECT_EQ(heightAt(map, 3.5, 3.5).state, CellState::kShadow);
  EXPECT_EQ(heightAt(map, -0.1, 1).state, CellState::kUnknown);
}

TEST(Queries, RegionsSelectCellsByTheirCentres) {
  const auto map = rampMap();
  // Triangle (0,0)-(4,0)-(0,4): centres with x + y < 4.
  const Polygon2 triangle{{{0, 0}, {4, 0}, {0, 4}}};
  const auto s = summarize(map, triangle);
  EXPECT_EQ(s.known, 6);
  EXPECT_DOUBLE_EQ(s.min_z, 0.0);
  EXPECT_DOUBLE_EQ(s.max_z, 2.0);
  EXPECT_NEAR(s.mean_z, (0 + 1 + 2 + 1 + 2 + 2) / 6.0, 1e-12);
  EXPECT_NEAR(s.mean_sigma, 0.1 / std::sqrt(6.0), 1e-6);
  const auto disk = summarize(map, Disk{{3.5, 3.5}, 1.1});  // (3,3) and its 4 neighbours
  EXPECT_EQ(disk.known, 2);
  EXPECT_EQ(disk.shadow, 1);
  const auto box = summarize(map, Box2{1, 1, 3, 3});
  EXPECT_EQ(box.cells(), 4);
}

TEST(Queries, ResampleAveragesCellsAndKeepsShadow) {
  const auto coarse = resample(rampMap(), 2.0);
  ASSERT_EQ(coarse.grid().rows, 2);
  EXPECT_FLOAT_EQ(coarse.elevation(0, 0), 1.0f);  // mean of 0, 1, 1, 2
  EXPECT_NEAR(coarse.sigma(0, 0), 0.05, 1e-6);
  EXPECT_FLOAT_EQ(coarse.elevation(1, 1), 14.0f / 3);  // 4, 5, 5; (3,3) is shadow
  const auto fine = resample(rampMap(), 0.5);
  EXPECT_FLOAT_EQ(fine.elevation(5, 2), 3.0f);  // inside source cell (2, 1)
  EXPECT_THROW(resample(rampMap(), 0.0), std::invalid_argument);
}

TEST(ElevationMapFile, RoundTrips) {
  TempDir dir;
  const auto map = rampMap();
  writeElevationMap(map, dir.path());
  const auto back = readElevationMap(dir.path());
  EXPECT_EQ(back.grid().rows, 4);
  EXPECT_EQ(back.frame(), "world");
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      EXPECT_EQ(back.state(r, c), map.state(r, c));
      if (map.isKnown(r, c)) {
        EXPECT_FLOAT_EQ(back.elevation(r, c), map.elevation(r, c));
      }
    }
  EXPECT_TRUE(std::isnan(io::readFloatTiff(dir / "elevation.tif")(3, 3)));
  EXPECT_EQ(io::readByteTiff(dir / "state.tif")(3, 3), 2);
}

// Writes a valid map, lets `spoil` break one thing, and expects the reader
// to refuse it with a message containing `expected`.
void expectRefused(const std::function<void(const std::filesystem::path&)>& spoil,
                   const std::string& expected) {
  TempDir dir;
  writeElevationMap(rampMap(), dir.path());
  spoil(dir.path());
  try {
    readElevationMap(dir.path());
    FAIL() << "accepted a map that should be refused (" << expected << ")";
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

// Ground seen only at a grazing angle: a height for matching scans and for
// clearances, never ground to stand on.
TEST(ElevationMap, AnObliqueCellHasAHeightButIsNotKnown) {
  auto map = rampMap();
  map.setHeight(0, 3, CellState::kOblique, 3.0, 0.1);
  for (int r : {2, 3})
    for (int c : {0, 1}) map.setHeight(r, c, CellState::kOblique, r + c, 0.1);
  EXPECT_FALSE(map.isKnown(0, 3));
  EXPECT_TRUE(map.hasHeight(0, 3));
  EXPECT_EQ(map.countOf(CellState::kOblique), 5);
  EXPECT_THROW(map.setHeight(0, 0, CellState::kShadow, 1.0, 0.1), std::invalid_argument);

  const auto e = heightAt(map, 3.5, 0.5);
  EXPECT_EQ(e.state, CellState::kOblique);
  EXPECT_DOUBLE_EQ(e.z, 3.0);
  const auto s = summarize(map, Box2{2, 0, 4, 2});  // cells (0..1, 2..3)
  EXPECT_EQ(s.known, 3);
  EXPECT_EQ(s.oblique, 1);
  EXPECT_DOUBLE_EQ(s.max_z, 4.0);
  EXPECT_DOUBLE_EQ(s.mean_z, 3.0);

  const auto coarse = resample(map, 2.0);
  EXPECT_EQ(coarse.state(0, 1), CellState::kKnown);  // known wins over oblique
  EXPECT_FLOAT_EQ(coarse.elevation(0, 1), 3.0f);
  EXPECT_EQ(coarse.state(1, 0), CellState::kOblique);
  EXPECT_FLOAT_EQ(coarse.elevation(1, 0), 3.0f);

  TempDir dir;
  writeElevationMap(map, dir.path());
  const auto back = readElevationMap(dir.path());
  EXPECT_EQ(back.state(0, 3), CellState::kOblique);
  EXPECT_FLOAT_EQ(back.elevation(0, 3), 3.0f);
  EXPECT_EQ(back.countOf(CellState::kOblique), 5);
  auto z = io::readFloatTiff(dir / "elevation.tif");
  z(0, 3) = NAN;
  io::writeTiff(dir / "elevation.tif", z);
  try {
    readElevationMap(dir.path());
    FAIL() << "read an oblique cell without a height";
  } catch (const io::FormatError& error) {
    EXPECT_NE(std::string(error.what()).find("cell (0, 3) is oblique but its elevation"),
              std::string::npos)
        << error.what();
  }
}

TEST(ElevationMapFile, RefusesBrokenMapsNamingTheProblem) {
  namespace fs = std::filesystem;
  expectRefused([](const fs::path& d) { fs::remove(d / "map.json"); }, "map.json");
  expectRefused([](const fs::path& d) { std::ofstream(d / "map.json") << "{\"rows\": 4"; },
                "map.json");
  expectRefused([](const fs::path& d) { io::writeTiff(d / "sigma.tif", io::FloatImage(3, 4)); },
                "sigma.tif");
  expectRefused(
      [](const fs::path& d) {
        auto state = io::readByteTiff(d / "state.tif");
        state(1, 2) = 7;
        io::writeTiff(d / "state.tif", state);
      },
      "unknown state code 7");
  expectRefused(
      [](const fs::path& d) {
        auto z = io::readFloatTiff(d / "elevation.tif");
        z(0, 1) = NAN;
        io::writeTiff(d / "elevation.tif", z);
      },
      "cell (0, 1) is known but its elevation is not finite");
  expectRefused(
      [](const fs::path& d) {
        std::ofstream(d / "map.json") << R"({"origin_x": 0, "origin_y": 0, "resolution": -1,
                                             "rows": 4, "cols": 4, "frame": "world"})";
      },
      "resolution");
}

}  // namespace
}  // namespace ambler::terrain

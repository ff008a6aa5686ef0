#include "terrain/Merge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "sim/ProceduralTerrain.h"
#include "sim/ScannerSim.h"
#include "terrain/Locus.h"

namespace ambler::terrain {
namespace {

TEST(Merge, TwoNoisyMapsOfTheSameGroundLowerSigmaByRootTwo) {
  sim::TerrainDescription d;
  d.extent = {-100, -100, 100, 100};
  const sim::ProceduralTerrain ground(d);
  const sim::RayCaster caster(ground);
  sim::ScannerModel m;
  m.geometry = sensor::ScanGeometry::symmetric(128, 128, 30 * M_PI / 180, 60 * M_PI / 180);
  m.range_sigma_k = 3e-4;
  const auto pose = m.mountPose({0, 0, 0});
  const GridSpec grid = GridSpec::covering({-3, 7, 3, 13}, 0.1);
  const auto a = buildLocusMap(sim::simulateScan(caster, m, pose, 1), grid);
  const auto b = buildLocusMap(sim::simulateScan(caster, m, pose, 2), grid);
  ElevationMap merged = a;
  mergeInto(merged, b);

  double sq_single = 0, sq_merged = 0;
  int n = 0;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      if (!a.isKnown(r, c) || !b.isKnown(r, c)) continue;
      const double wa = 1 / std::pow(a.sigma(r, c), 2), wb = 1 / std::pow(b.sigma(r, c), 2);
      ASSERT_NEAR(merged.sigma(r, c), 1 / std::sqrt(wa + wb), 1e-6);
      ASSERT_NEAR(merged.elevation(r, c),
                  (wa * a.elevation(r, c) + wb * b.elevation(r, c)) / (wa + wb), 1e-6);
      EXPECT_EQ(merged.count(r, c), 2);
      sq_single += 0.5 * (std::pow(a.elevation(r, c), 2) + std::pow(b.elevation(r, c), 2));
      sq_merged += std::pow(merged.elevation(r, c), 2);
      ++n;
    }
  ASSERT_GT(n, 2000);
  // The ground is at z = 0, so the heights are the errors: their RMS falls
  // by 1/sqrt(2), as the sigmas say.
  EXPECT_NEAR(std::sqrt(sq_merged / sq_single), 1 / std::sqrt(2.0), 0.05);
}

TEST(Merge, ShadowSeenFromASecondPositionBecomesKnown) {
  ElevationMap map(GridSpec::covering({0, 0, 1, 1}, 0.5));
  map.setUnobserved(0, 0, CellState::kShadow);
  map.setKnown(0, 1, 2.0, 0.1);
  ElevationMap update(map.grid());
  update.setKnown(0, 0, 1.0, 0.2);
  update.setUnobserved(0, 1, CellState::kShadow);
  update.setUnobserved(1, 0, CellState::kShadow);
  mergeInto(map, update);
  EXPECT_EQ(map.state(0, 0), CellState::kKnown);
  EXPECT_FLOAT_EQ(map.elevation(0, 0), 1.0f);
  EXPECT_EQ(map.state(0, 1), CellState::kKnown);  // shadow never erases a height
  EXPECT_FLOAT_EQ(map.elevation(0, 1), 2.0f);
  EXPECT_EQ(map.state(1, 0), CellState::kShadow);  // shadow wins over unknown
  EXPECT_EQ(map.state(1, 1), CellState::kUnknown);
}

TEST(Merge, AnObliqueHeightIsFusedButOnlyAKnownOneMakesTheCellKnown) {
  ElevationMap map(GridSpec::covering({0, 0, 1, 1}, 0.5));
  map.setHeight(0, 0, CellState::kOblique, 1.0, 0.1);
  map.setHeight(0, 1, CellState::kOblique, 1.0, 0.1);
  map.setKnown(1, 0, 1.0, 0.1);
  map.setUnobserved(1, 1, CellState::kShadow);
  ElevationMap update(map.grid());
  update.setKnown(0, 0, 2.0, 0.1);
  update.setHeight(0, 1, CellState::kOblique, 2.0, 0.1);
  update.setHeight(1, 0, CellState::kOblique, 2.0, 0.1);
  update.setHeight(1, 1, CellState::kOblique, 3.0, 0.2);
  mergeInto(map, update);
  for (const auto& [r, c] : {std::pair{0, 0}, {0, 1}, {1, 0}}) {
    EXPECT_FLOAT_EQ(map.elevation(r, c), 1.5f) << r << ", " << c;
    EXPECT_NEAR(map.sigma(r, c), 0.1 / std::sqrt(2.0), 1e-6);
    EXPECT_EQ(map.count(r, c), 2);
  }
  EXPECT_EQ(map.state(0, 0), CellState::kKnown);    // seen squarely once
  EXPECT_EQ(map.state(0, 1), CellState::kOblique);  // never
  EXPECT_EQ(map.state(1, 0), CellState::kKnown);
  EXPECT_EQ(map.state(1, 1), CellState::kOblique);  // a height wins over shadow
  EXPECT_FLOAT_EQ(map.elevation(1, 1), 3.0f);
}

TEST(Merge, RefusesMapsInDifferentFrames) {
  ElevationMap map(GridSpec::covering({0, 0, 1, 1}, 0.5), "world");
  const ElevationMap update(map.grid(), "rover");
  EXPECT_THROW(mergeInto(map, update), std::invalid_argument);
}

}  // namespace
}  // namespace ambler::terrain

// Constraint cost maps of the gait planner (cmu-1990 'Footfalls', Table 1)
// and their configuration file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/Resources.h"
#include "footfall/CostMaps.h"
#include "footfall/FootfallConfig.h"
#include "io/FormatError.h"

namespace ambler::footfall {
namespace {

using terrain::ElevationMap;

// Flat ground at 5 cm over [-3, 3]^2, sigma 1 mm, with a 1.5 m high block
// over [1, 1.6] x [-0.3, 0.3].
ElevationMap groundWithBlock() {
  ElevationMap map(GridSpec::covering({-3, -3, 3, 3}, 0.05));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) {
      const auto p = map.grid().cellCenter(r, c);
      const bool block = p.x() > 1.0 && p.x() < 1.6 && std::abs(p.y()) < 0.3;
      map.setKnown(r, c, block ? 1.5 : 0.0, 0.001);
    }
  return map;
}

TEST(CostMaps, BodyAdvanceKeepsTheFootWithinReach) {
  LegContext leg;                                                // shaft at the origin, heading +y
  EXPECT_NEAR(bodyAdvance({0, 1}, leg, 2.5, 10), 3.5, 1e-12);    // 1 + 2.5
  EXPECT_NEAR(bodyAdvance({1.5, 0}, leg, 2.5, 10), 2.0, 1e-12);  // sqrt(2.5^2 - 1.5^2)
  EXPECT_NEAR(bodyAdvance({0, 1}, leg, 2.5, 1.5), 1.5, 1e-12);   // the planner's threshold
  EXPECT_EQ(bodyAdvance({3, 0}, leg, 2.5, 10), 0.0);             // out of reach already
}

TEST(CostMaps, VisibilityIsTheShareOfTheLinkInTheScannersView) {
  const ScannerView scanner{{0, -1}, M_PI / 2, M_PI / 3};
  EXPECT_EQ(linkInView({0, 2}, {0, 0}, scanner), 1.0);
  // Along the x axis the link is in view while x <= tan(30 deg) * 1 m.
  EXPECT_NEAR(linkInView({2, 0}, {0, 0}, scanner), std::tan(M_PI / 6) / 2, 1e-12);
  EXPECT_EQ(linkInView({0, -2}, {0, -1.5}, scanner), 0.0);  // behind the scanner
  // A 270 degree view misses only the quarter behind it.
  const ScannerView wide{{0, 0}, M_PI / 2, 1.5 * M_PI};
  EXPECT_NEAR(linkInView({1, -1}, {-1, -1}, wide), 0.0, 1e-12);
  EXPECT_NEAR(linkInView({2, -1}, {-2, -1}, wide), 0.5, 1e-12);
  EXPECT_NEAR(linkInView({1, 1}, {-1, 1}, wide), 1.0, 1e-12);
}

TEST(CostMaps, DiscreteConstraintsThresholdTheComposite) {
  const auto map = groundWithBlock();
  LegContext leg;
  CostMapOptions o;
  const auto m = buildCostMaps(map, {-2.8, -2.8, 2.8, 2.8}, leg, o);
  auto at = [&](const ScoreMap& s, double x, double y) {
    const auto cell = s.grid.cellAt(x, y);
    return cell ? double(s.score(cell->row, cell->col)) : NAN;
  };
  EXPECT_TRUE(std::isnan(at(m.composite, 0.0, 0.5))) << "closer than the minimum reach";
  EXPECT_TRUE(std::isnan(at(m.composite, 0.0, 2.7))) << "beyond the maximum reach";
  EXPECT_TRUE(std::isnan(at(m.composite, 1.3, 0.0))) << "on the block, above the limit";
  EXPECT_FALSE(std::isnan(at(m.roughness, 1.3, 0.0))) << "the block's top itself is smooth";
  const double composite = at(m.composite, -1.5, 0.5);
  ASSERT_TRUE(std::isfinite(composite));
  const auto& w = o.weights;
  EXPECT_NEAR(composite,
              w.roughness * at(m.roughness, -1.5, 0.5) + w.slope * at(m.slope, -1.5, 0.5) +
                  w.body_advance * at(m.body_advance, -1.5, 0.5),
              1e-5);
  // Feet straddling the block's edge are rough.
  EXPECT_EQ(at(m.roughness, 1.0, 0.0), 1.0);
}

TEST(CostMaps, BestFootholdFollowsTheWeights) {
  const auto map = groundWithBlock();
  LegContext leg;
  leg.heading_rad = 0.0;  // towards the block
  CostMapOptions o;
  o.max_body_advance_m = 10;
  o.weights = {0, 0, 1, 0};  // advance alone: the foot as far ahead as it reaches
  auto best = bestFoothold(buildCostMaps(map, {-2.8, -2.8, 2.8, 2.8}, leg, o).composite);
  ASSERT_TRUE(best.found);
  EXPECT_NEAR(best.x, 2.5, 0.05);
  EXPECT_NEAR(best.y, 0.0, 0.05);
  // With a scanner looking along +x from behind the shaft, visibility
  // pushes the foot out of its view, to either side.
  leg.scanner = ScannerView{{-1, 0}, 0.0, M_PI / 3};
  o.weights = {0, 0, 0.1, 1};
  best = bestFoothold(buildCostMaps(map, {-2.8, -2.8, 2.8, 2.8}, leg, o).composite);
  ASSERT_TRUE(best.found);
  EXPECT_GT(std::abs(best.y), 1.0);
}

TEST(CostMaps, ShippedConfigurationReads) {
  const auto o = readFootfallConfig(findResource("config/footfall.json"));
  EXPECT_EQ(o.foot.diameter_m, 0.30);
  EXPECT_EQ(o.max_body_advance_m, 1.5);
  EXPECT_EQ(o.roughness_criterion, Criterion::kEquilibrium);
}

TEST(CostMaps, BadConfigurationNamesTheKey) {
  const auto path = std::filesystem::temp_directory_path() / "ambler_footfall_bad.json";
  auto expectError = [&](const std::string& text, const std::string& needle) {
    std::ofstream(path) << text;
    try {
      readFootfallConfig(path);
      ADD_FAILURE() << "accepted " << text;
    } catch (const io::FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectError(R"({"foot": {"diameter_m": -0.3}})", "diameter_m");
  expectError(R"({"limits": {"reach_min_m": 3, "reach_max_m": 2}})", "reach");
  expectError(R"({"roughness": {"criterion": "bumpiness"}})", "bumpiness");
  expectError(R"({"weights": {"slope": "heavy"}})", "slope");
  expectError(R"({"foot": )", "footfall_bad.json");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ambler::footfall

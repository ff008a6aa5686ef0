#include "sim/TerrainFamilies.h"

#include <gtest/gtest.h>

#include <random>

namespace ambler::sim {
namespace {

std::vector<Superquadric> rocksOf(const TerrainDescription& d) {
  std::vector<Superquadric> rocks;
  for (const auto& f : d.features)
    if (const auto* r = std::get_if<Rock>(&f)) rocks.push_back(r->shape);
  return rocks;
}

// The share of area covered by rocks of diameter >= d follows the
// Golombek-Rapp model k exp(-q d) (cut off at d_max).
TEST(RockField, AreaCoveredFollowsGolombekRapp) {
  for (const double k : {0.05, 0.15, 0.30}) {
    // Pooled over seeds: metre-sized rocks are few in one field.
    double area = 0.0, covered_02 = 0.0, covered_05 = 0.0, covered_1 = 0.0;
    RockFieldOptions o{.abundance = k};
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      o.seed = seed;
      area += o.extent.width() * o.extent.height();
      for (const auto& r : rocksOf(makeRockField(o))) {
        const double d = 2 * std::sqrt(r.size.x() * r.size.y()), a = M_PI * r.size.x() * r.size.y();
        covered_02 += d >= 0.2 ? a : 0.0;
        covered_05 += d >= 0.5 ? a : 0.0;
        covered_1 += d >= 1.0 ? a : 0.0;
      }
    }
    const double q = 1.79 + 0.152 / k;
    auto expected = [&](double d) { return k * (std::exp(-q * d) - std::exp(-q * o.d_max)); };
    EXPECT_NEAR(covered_02 / area, expected(0.2), 0.1 * expected(0.2)) << "k " << k;
    EXPECT_NEAR(covered_05 / area, expected(0.5), 0.15 * expected(0.5)) << "k " << k;
    // At 5 % the pooled fields hold a handful of metre-sized rocks.
    if (k > 0.1) {
      EXPECT_NEAR(covered_1 / area, expected(1.0), 0.3 * expected(1.0)) << "k " << k;
    }
  }
}

TEST(RockField, KeepsTheStartAreaClear) {
  const ProceduralTerrain t(makeRockField({.seed = 3, .abundance = 0.3}));
  for (double x = -1.4; x <= 1.4; x += 0.1) EXPECT_EQ(t.featureAt(x, 0.0), -1);
}

TEST(Crater, ProfileHasRimBowlAndEjecta) {
  const Crater c{0.0, 0.0, 4.0, 0.8, 0.16};
  EXPECT_NEAR(c.relief(0, 0), 0.16 - 0.8, 1e-12);  // floor: depth below the rim crest
  EXPECT_NEAR(c.relief(2.0, 0), 0.16, 1e-12);      // rim crest at R
  EXPECT_NEAR(c.relief(2.0 + 1e-9, 0), 0.16, 1e-6);
  EXPECT_NEAR(c.relief(0, -6.0), 0.0, 1e-12);  // ejecta ends at 3 R
  EXPECT_EQ(c.relief(6.5, 0), 0.0);
  EXPECT_GT(c.relief(3.0, 0), 0.0);
  EXPECT_LT(c.relief(3.0, 0), c.relief(2.5, 0));
}

TEST(CraterField, SizesFollowThePowerLawAndDepthRatio) {
  CraterFieldOptions o{.seed = 11, .density_1m = 0.05};
  const auto d = makeCraterField(o);
  ASSERT_GT(d.craters.size(), 300u);
  for (const auto& c : d.craters) {
    EXPECT_GE(c.depth / c.diameter, o.depth_ratio_min);
    EXPECT_LE(c.depth / c.diameter, o.depth_ratio_max);
  }
  // Cumulative counts at 0.5 and 2 m: N(>=2) / N(>=0.5) = (2 / 0.5)^-b for
  // the truncated law (1/16 for b = 2, less the share cut at d_max).
  auto atLeast = [&](double dd) {
    return double(std::count_if(d.craters.begin(), d.craters.end(),
                                [&](const Crater& c) { return c.diameter >= dd; }));
  };
  const double lo = std::pow(0.5, -2.0), hi = std::pow(12.0, -2.0);
  const double expected = (std::pow(2.0, -2.0) - hi) / (lo - hi);
  EXPECT_NEAR(atLeast(2.0) / atLeast(0.5), expected, 0.25 * expected);
  // The ground at a crater's centre is its floor.
  const ProceduralTerrain t(d);
  const auto& c = d.craters.front();
  EXPECT_LT(t.height(c.cx, c.cy), t.height(c.cx + c.radius(), c.cy));
}

// The structure function of fBm ground grows as lag^H.
TEST(RoughGround, StructureFunctionFollowsHurst) {
  for (const double hurst : {0.5, 0.8}) {
    const RoughGroundOptions o{.seed = 5, .hurst = hurst, .rms_1m = 0.05};
    const auto d = makeRoughGround(o);
    EXPECT_NEAR(roughnessAt(d.waves, 1.0), 0.05, 1e-9);
    const ProceduralTerrain t(d);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<> x(-15, 15), y(-5, 45), angle(0, 2 * M_PI);
    auto measured = [&](double lag) {
      double sum = 0.0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        const double px = x(rng), py = y(rng), a = angle(rng);
        const double dz =
            t.height(px + lag * std::cos(a), py + lag * std::sin(a)) - t.height(px, py);
        sum += dz * dz;
      }
      return std::sqrt(sum / n);
    };
    // The terrain as built matches the expectation, and the expectation
    // grows as lag^H inside the band (it flattens towards its ends).
    for (const double lag : {0.25, 0.5, 1.0, 2.0})
      EXPECT_NEAR(measured(lag), roughnessAt(d.waves, lag), 0.1 * roughnessAt(d.waves, lag));
    const double slope =
        std::log(roughnessAt(d.waves, 1.0) / roughnessAt(d.waves, 0.25)) / std::log(4.0);
    EXPECT_NEAR(slope, hurst, 0.1) << "H " << hurst;
  }
}

TEST(NegativeObstacles, DitchesAreVShapedAndTrenchesFlat) {
  const auto d = makeNegativeObstacles({.seed = 2});
  const ProceduralTerrain t(d);
  int ditches = 0, trenches = 0, steps = 0;
  for (const auto& f : d.features) {
    const auto& tr = std::get<Trench>(f);
    const auto& fp = tr.footprint;
    const double rim = t.groundHeight(fp.cx, fp.cy);
    if (fp.half_x > 50) {
      ++steps;
      EXPECT_GE(tr.depth, 0.3);
      continue;
    }
    const Eigen::Vector2d across(-std::sin(fp.yaw), std::cos(fp.yaw));
    auto at = [&](double v) {
      return t.height(fp.cx + v * fp.half_y * across.x(), fp.cy + v * fp.half_y * across.y());
    };
    EXPECT_NEAR(at(0.0), rim - tr.depth, 1e-9);
    if (tr.wall_run > 0) {
      ++ditches;
      EXPECT_NEAR(at(0.5), rim - 0.5 * tr.depth, 1e-9);
    } else {
      ++trenches;
      EXPECT_NEAR(at(0.9), rim - tr.depth, 1e-9);
    }
  }
  EXPECT_EQ(trenches, 3);
  EXPECT_EQ(ditches, 2);
  EXPECT_EQ(steps, 1);
}

TEST(Slope, GroundRisesAtTheStatedAngle) {
  const double uphill = 1.0;
  const ProceduralTerrain t(makeSlope({.seed = 4, .slope_deg = 25, .uphill = uphill}));
  const Eigen::Vector2d up(std::cos(uphill), std::sin(uphill)), across(-up.y(), up.x());
  // Rise over 10 m uphill, averaged along a line across the slope to
  // average out the rolling ground.
  double rise = 0.0;
  int n = 0;
  for (double s = -8; s <= 8; s += 0.5, ++n) {
    const Eigen::Vector2d p = Eigen::Vector2d(0, 10) + s * across;
    rise += t.groundHeight(p.x() + 5 * up.x(), p.y() + 5 * up.y()) -
            t.groundHeight(p.x() - 5 * up.x(), p.y() - 5 * up.y());
  }
  EXPECT_NEAR(std::atan(rise / n / 10.0) * 180 / M_PI, 25.0, 1.5);
}

// The ray caster skips space above maxHeightIn(): it must bound every
// family's heights.
TEST(TerrainFamilies, MaxHeightBoundsEveryFamily) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<> x(-18, 16), y(-8, 46), size(0.2, 3.0);
  for (const auto family : kTerrainFamilies) {
    const ProceduralTerrain t(makeFamilyTerrain(family, 9));
    for (int i = 0; i < 200; ++i) {
      const double x0 = x(rng), y0 = y(rng), s = size(rng);
      const Box2 box{x0, y0, x0 + s, y0 + s};
      const double bound = t.maxHeightIn(box);
      for (double px = box.x_min; px <= box.x_max; px += 0.05)
        for (double py = box.y_min; py <= box.y_max; py += 0.05)
          ASSERT_LE(t.height(px, py), bound + 1e-9) << familyName(family);
    }
  }
}

TEST(TerrainFamilies, SeedsAreRepeatableAndNamesRoundTrip) {
  for (const auto family : kTerrainFamilies) {
    EXPECT_EQ(parseFamily(familyName(family)), family);
    const ProceduralTerrain a(makeFamilyTerrain(family, 1001)), b(makeFamilyTerrain(family, 1001));
    const ProceduralTerrain c(makeFamilyTerrain(family, 1002));
    EXPECT_EQ(a.height(3.3, 12.7), b.height(3.3, 12.7));
    EXPECT_NE(a.height(3.3, 12.7), c.height(3.3, 12.7));
  }
  EXPECT_FALSE(parseFamily("moon"));
  for (const auto s : kTuningSeeds)
    EXPECT_EQ(std::count(kEvaluationSeeds.begin(), kEvaluationSeeds.end(), s), 0);
}

}  // namespace
}  // namespace ambler::sim

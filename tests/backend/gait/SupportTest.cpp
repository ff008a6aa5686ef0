// Support polygon, conservative support polygon and stability margin
// (cmu-1990 'Planning strategies', figs. 4-5) against analytic cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "gait/Support.h"

namespace ambler::gait {
namespace {

using V = Eigen::Vector2d;

TEST(Support, HullDropsInteriorAndCollinearPoints) {
  const ConvexPolygon hull = convexHull({{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}, {1, 0}});
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_NEAR(area(hull), 4.0, 1e-12);
  EXPECT_NEAR(stabilityMargin(hull, {1, 1}), 1.0, 1e-12);
  EXPECT_NEAR(stabilityMargin(hull, {1, 0.25}), 0.25, 1e-12);
  EXPECT_NEAR(stabilityMargin(hull, {3, 1}), -1.0, 1e-12);  // outside: minus the distance
}

// Six feet at x = +-2, y = -2, 0, 2. Removing a corner foot cuts the
// rectangle along the line from the same side's middle foot to the
// opposite rear (or front) corner; removing a middle foot changes nothing.
// The CSP is the rhombus (-2, 0), (0, -1), (2, 0), (0, 1): area 4, and the
// centre lies 2 / sqrt(5) from its edges.
const std::vector<V> kRectangle{{-2, -2}, {-2, 0}, {-2, 2}, {2, -2}, {2, 0}, {2, 2}};

TEST(Support, ConservativeSupportPolygonOfTheSixLegStanceIsTheAnalyticRhombus) {
  const ConvexPolygon csp = conservativeSupportPolygon(kRectangle);
  EXPECT_NEAR(area(csp), 4.0, 1e-9);
  EXPECT_NEAR(stabilityMargin(csp, {0, 0}), 2.0 / std::sqrt(5.0), 1e-9);
  EXPECT_NEAR(conservativeMargin(kRectangle, {0, 0}), 2.0 / std::sqrt(5.0), 1e-9);
  EXPECT_LT(stabilityMargin(csp, {0, 1.2}), 0.0);  // inside the support polygon, not the CSP
  EXPECT_GT(stabilityMargin(supportPolygon(kRectangle), {0, 1.2}), 0.0);
}

TEST(Support, FewerThanFourFeetHaveNoConservativeSupport) {
  EXPECT_TRUE(conservativeSupportPolygon({{0, 0}, {1, 0}, {0, 1}}).empty());
  EXPECT_EQ(conservativeMargin({{0, 0}, {1, 0}, {0, 1}}, {0.2, 0.2}),
            -std::numeric_limits<double>::infinity());
}

// Regression: far from the origin, clipping produced a near-duplicate
// vertex whose zero-length edge flipped the inside test (a walk at y = 15 m
// reported -0.527 m for a centre of gravity 0.525 m inside).
TEST(Support, MarginDoesNotDependOnWhereTheStanceIs) {
  const std::vector<V> body{{-2.30, 0.02}, {-2.16, 1.25}, {-2.50, -1.53},
                            {2.44, 0.28},  {2.15, 1.79},  {2.30, -1.10}};
  const double local = stabilityMargin(conservativeSupportPolygon(body), {0, 0});
  EXPECT_NEAR(local, 0.5247, 1e-3);
  const Eigen::Rotation2Dd r(0.012);
  const V offset(-0.06, 15.23);
  std::vector<V> world;
  for (const auto& f : body) world.push_back(offset + r * f);
  EXPECT_NEAR(stabilityMargin(conservativeSupportPolygon(world), offset), local, 1e-9);
  EXPECT_NEAR(conservativeMargin(world, offset), local, 1e-9);
}

// The defining property: with the centre of gravity inside the CSP, it
// stays inside the support polygon of the feet left after any one fails;
// and the fast margin equals the polygon's wherever it is positive.
TEST(Support, InsideTheCspSurvivesTheLossOfAnyOneLeg) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.6, 0.6), point(-1.5, 1.5);
  int inside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<V> feet;
    for (const auto& f : kRectangle) feet.push_back(f + V(jitter(rng), jitter(rng)));
    const V p(point(rng), point(rng));
    const double fast = conservativeMargin(feet, p);
    const double exact = stabilityMargin(conservativeSupportPolygon(feet), p);
    EXPECT_EQ(fast > 0, exact > 0);
    if (exact <= 0) continue;
    ++inside;
    EXPECT_NEAR(fast, exact, 1e-9);
    for (std::size_t lost = 0; lost < feet.size(); ++lost) {
      std::vector<V> rest = feet;
      rest.erase(rest.begin() + long(lost));
      EXPECT_GE(stabilityMargin(convexHull(rest), p), exact - 1e-9);
    }
  }
  EXPECT_GT(inside, 200);  // the property was exercised
}

}  // namespace
}  // namespace ambler::gait

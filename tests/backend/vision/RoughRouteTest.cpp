// ejiri §4: the rough route and the sensing plan on images with known
// dark rough patches.
#include "vision/RoughRoute.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "vision/DangerMap.h"

namespace ambler::vision {
namespace {

// Sand (200 +- 3) with dark rough rectangles (90 +- 40); rows from the top.
io::FloatImage sandWith(const std::vector<std::array<int, 4>>& rocks, int rows = 480,
                        int cols = 640) {
  std::mt19937 rng(5);
  std::normal_distribution<float> sand(200.0f, 3.0f), rock(90.0f, 40.0f);
  io::FloatImage image(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      bool in = false;
      for (const auto& [r0, r1, c0, c1] : rocks) in |= r >= r0 && r < r1 && c >= c0 && c < c1;
      image(r, c) = in ? rock(rng) : sand(rng);
    }
  return image;
}

const CameraModel kCamera{.rows = 480, .alpha_deg = 78, .beta_deg = 40};

// Every point of every leg has a free corridor (D at most the threshold).
void expectLegsClear(const io::FloatImage& d, const RoughRoute& r) {
  for (std::size_t i = 0; i + 1 < r.route.size(); ++i)
    for (double s = 0; s <= 1.0; s += 0.002) {
      const double x = r.route[i].x + s * (r.route[i + 1].x - r.route[i].x);
      const double y = r.route[i].y + s * (r.route[i + 1].y - r.route[i].y);
      const float v = d(d.rows - 1 - int(std::lround(y)), int(std::lround(x)));
      ASSERT_LE(v, r.threshold) << "leg " << i << " at x " << x << ", y " << y;
    }
}

TEST(RoughRoute, OpenGroundIsOneStraightLegSensedFromAfar) {
  const auto d = degreeOfDanger(sandWith({}), kCamera);
  const auto r = planRoughRoute(d, kCamera);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_TRUE(r.way_areas.empty());
  EXPECT_FALSE(r.start_moved || r.destination_moved);
  const auto plan = planSensing(d, kCamera, r);
  ASSERT_GE(plan.size(), 3u);
  EXPECT_EQ(plan.front().action, SensingAction::kF);  // at the start point
  EXPECT_EQ(plan.back().action, SensingAction::kE);   // at the long-distance band
  for (std::size_t i = 1; i + 1 < plan.size(); ++i) EXPECT_EQ(plan[i].action, SensingAction::kA);
}

// A rock field across the straight route in the middle distance: the route
// turns at a Way Area beside it, to the side it leaves the route less, and
// no leg's corridor crosses a dangerous pixel.
TEST(RoughRoute, AnObstacleAheadIsPassedAtAWayArea) {
  const auto d = degreeOfDanger(sandWith({{300, 330, 250, 420}}), kCamera);
  const auto r = planRoughRoute(d, kCamera);
  ASSERT_TRUE(r.found) << r.reason;
  ASSERT_FALSE(r.way_areas.empty());
  EXPECT_LT(r.way_areas.front().x, 250);  // the obstacle reaches further right
  expectLegsClear(d, r);
  // Beside the obstacle the plan asks for more care than on open ground.
  const auto plan = planSensing(d, kCamera, r);
  EXPECT_TRUE(std::any_of(plan.begin(), plan.end(), [](const SensingStep& s) {
    return s.action == SensingAction::kC || s.action == SensingAction::kD;
  }));
}

// A rock on the start area: the start moves sideways onto safe sand.
TEST(RoughRoute, AStartInDangerMovesToSafeGround) {
  const auto d = degreeOfDanger(sandWith({{430, 480, 280, 360}}), kCamera);
  const auto r = planRoughRoute(d, kCamera);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_TRUE(r.start_moved);
  EXPECT_TRUE(r.start.x < 280 || r.start.x >= 360) << r.start.x;
  expectLegsClear(d, r);
}

}  // namespace
}  // namespace ambler::vision

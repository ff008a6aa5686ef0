// ejiri §3: window widths against a pinhole camera's projection of the
// ground, and the degree of danger on images with known answers.
#include "vision/DangerMap.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <random>

#include "core/Angles.h"

namespace ambler::vision {
namespace {

// The row, from the bottom, where a pinhole camera H above flat ground,
// its axis alpha from the nadir, sees the ground point `x` ahead.
double projectedRow(const CameraModel& c, double x) {
  const double a = c.alpha_deg * kDeg;
  const Eigen::Vector2d axis(std::sin(a), -std::cos(a)), up(std::cos(a), std::sin(a));
  const Eigen::Vector2d v(x, -c.height_m);
  const double f = c.rows / (2 * std::tan(0.5 * c.beta_deg * kDeg));
  return 0.5 * c.rows + f * (v.dot(up) / v.dot(axis));
}

TEST(DangerMap, WindowWidthsAreTheImageOfTheirGroundSpans) {
  const CameraModel c{.rows = 480, .alpha_deg = 62, .beta_deg = 44, .height_m = 1.6};
  const double x0 = c.height_m * std::tan((c.alpha_deg - 0.5 * c.beta_deg) * kDeg);
  EXPECT_NEAR(projectedRow(c, x0), 0.0, 1e-9);  // the lower edge of the view
  for (const double d : {c.wheel_diameter_m, c.rover_diagonal_m})
    for (int k = 0; k < 12; ++k) {
      const double near = k < 2 ? x0 : x0 + (k - 1) * d / 2, far = x0 + (k + 1) * d / 2;
      EXPECT_NEAR(rowAt(c, windowAngle(c, k, d)), projectedRow(c, far), 1e-9) << k;
      EXPECT_NEAR(windowWidth(c, k, d), projectedRow(c, far) - projectedRow(c, near), 1e-9)
          << "k " << k << ", d " << d;
    }
}

TEST(DangerMap, BandsFollowTheWindowsAndTheHorizon) {
  // Looking 10 deg below the horizontal with a 40 deg view: the horizon is
  // 10 deg above the axis, and the windows narrow to 2 pixels below it.
  const CameraModel c{.rows = 480, .alpha_deg = 80, .beta_deg = 40};
  const double f = 240 / std::tan(20 * kDeg);
  const Bands b = bandsOf(c);
  EXPECT_NEAR(b.y_h, 240 + f * std::tan(10 * kDeg), 1.0);
  EXPECT_GT(b.y_v, 0);
  EXPECT_LT(b.y_v, b.y_g);
  EXPECT_LT(b.y_g, b.y_h);
  // y_g and y_v: where the last window wider than 2 pixels ends.
  for (const auto& [d, y] : {std::pair{c.rover_diagonal_m, b.y_g}, {c.wheel_diameter_m, b.y_v}}) {
    double end = 0;
    for (int k = 0; windowWidth(c, k, d) > 2; ++k) end = rowAt(c, windowAngle(c, k, d));
    EXPECT_NEAR(y, end, 1.0) << d;
  }
  // Looking 30 deg below the horizontal, the view ends below the horizon.
  EXPECT_EQ(bandsOf(CameraModel{.rows = 480, .alpha_deg = 60, .beta_deg = 40}).y_h, 480);
}

TEST(DangerMap, EvenGroundIsOneMinusItsShade) {
  const CameraModel c{.rows = 240, .alpha_deg = 80, .beta_deg = 40};
  const io::FloatImage flat(240, 320, 204.0f);
  const auto d = degreeOfDanger(flat, c);
  const int y_h = bandsOf(c).y_h;
  for (int r = 0; r < 240; ++r)
    for (int col = 0; col < 320; col += 7) {
      if (240 - 1 - r >= y_h)
        EXPECT_TRUE(std::isnan(d(r, col))) << r;  // sky
      else
        EXPECT_NEAR(d(r, col), 1.0 - 204.0 / 255.0, 1e-6) << r << " " << col;
    }
}

// Bright sand with a little noise, and dark rough patches (rocks) in the
// near band: at a threshold of 0.5 the patches are found (recall >= 0.9),
// and sand 60 pixels away from them almost never (the large shade windows
// near the bottom of the image spread a patch's darkness further).
TEST(DangerMap, DarkRoughPatchesAreDangerous) {
  const CameraModel c{.rows = 480, .alpha_deg = 60, .beta_deg = 40};
  std::mt19937 rng(3);
  std::normal_distribution<float> sand(200.0f, 3.0f), rock(90.0f, 40.0f);
  io::FloatImage image(480, 640);
  struct Patch {
    int r0, r1, c0, c1;
  };
  const std::vector<Patch> patches{
      {400, 440, 100, 160}, {330, 380, 400, 470}, {420, 470, 520, 560}};
  auto inside = [&](int r, int col, int margin) {
    for (const auto& p : patches)
      if (r >= p.r0 - margin && r < p.r1 + margin && col >= p.c0 - margin && col < p.c1 + margin)
        return true;
    return false;
  };
  for (int r = 0; r < 480; ++r)
    for (int col = 0; col < 640; ++col) image(r, col) = inside(r, col, 0) ? rock(rng) : sand(rng);
  const auto d = degreeOfDanger(image, c);
  int in = 0, found = 0, out = 0, false_alarms = 0;
  for (int r = 0; r < 480; ++r)
    for (int col = 0; col < 640; ++col) {
      if (inside(r, col, 0)) ++in, found += d(r, col) > 0.5;
      if (!inside(r, col, 60) && r > 300) ++out, false_alarms += d(r, col) > 0.5;
    }
  EXPECT_GE(double(found) / in, 0.9) << found << " of " << in;
  EXPECT_LT(double(false_alarms) / out, 0.01) << false_alarms << " of " << out;
}

TEST(DangerMap, BadInputIsRefusedWithTheProblemNamed) {
  const CameraModel c{.rows = 480};
  try {
    degreeOfDanger(io::FloatImage(400, 640, 100.0f), c);
    ADD_FAILURE() << "a 400-row image was taken for a 480-row camera";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("400 rows"), std::string::npos) << e.what();
  }
  CameraModel up = c;
  up.alpha_deg = 15;  // the view's lower edge behind the nadir
  EXPECT_THROW(bandsOf(up), std::invalid_argument);
}

}  // namespace
}  // namespace ambler::vision

// Shaded camera images of the course (the input of the danger map):
// Lambert's law on flat sand, a box marked rough and casting its shadow.
#include "sim/CameraRender.h"

#include <gtest/gtest.h>

#include <cmath>

#include "backend/sim/FlatGround.h"

namespace ambler::sim {
namespace {

TEST(CameraRender, FlatSandFollowsLambertAndTheSkyIsBlack) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  const CameraShot shot{.rows = 120, .cols = 160, .alpha_deg = 80, .beta_deg = 40};
  const auto image = renderCamera(ground, caster, shot);
  // Albedo 0.85 under a sun 35 deg high, ambient 0.12, gain 1.6; 2 % grain.
  const double lit = 255 * 0.85 * (0.12 + 0.88 * std::sin(35 * M_PI / 180)) * 1.6;
  double sum = 0;
  int n = 0;
  for (int r = 80; r < 120; ++r)
    for (int c = 0; c < 160; ++c) {
      sum += image.grey(r, c), ++n;
      EXPECT_EQ(image.rough(r, c), 0);
    }
  EXPECT_NEAR(sum / n, lit, 0.01 * lit);
  EXPECT_EQ(image.grey(0, 80), 0.0f);  // 10 deg above the horizon
  EXPECT_EQ(image.rough(0, 80), 255);
}

// A 1 m box 6 m ahead: its pixels are rough; the sun behind-left of the
// camera throws its shadow to the front-right, darker than any lit sand.
TEST(CameraRender, ABoxIsRoughAndCastsAShadow) {
  const auto ground = flatGround({BoxObstacle{{0.0, 6.0, 0.0, 0.5, 0.5}, 1.0}});
  const RayCaster caster(ground);
  const CameraShot shot{.rows = 240,
                        .cols = 320,
                        .alpha_deg = 75,
                        .beta_deg = 40,
                        .sun_elevation_deg = 20,
                        .sun_azimuth_deg = 150};
  const auto image = renderCamera(ground, caster, shot);
  int rough = 0, shadow = 0;
  for (int r = 0; r < 240; ++r)
    for (int c = 0; c < 320; ++c) {
      rough += image.rough(r, c) == 1;
      shadow += image.rough(r, c) == 0 && image.grey(r, c) < 60;
    }
  EXPECT_GT(rough, 200);
  EXPECT_GT(shadow, 100);
}

}  // namespace
}  // namespace ambler::sim

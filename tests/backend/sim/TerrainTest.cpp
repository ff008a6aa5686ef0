#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "TempDir.h"
#include "core/Resources.h"
#include "io/Tiff.h"
#include "sim/CourseScene.h"
#include "sim/HeightfieldTerrain.h"
#include "sim/ObstacleCourse.h"

namespace ambler::sim {
namespace {

template <typename T>
const T* findFeature(const TerrainDescription& d, int* index = nullptr) {
  for (std::size_t i = 0; i < d.features.size(); ++i)
    if (const auto* f = std::get_if<T>(&d.features[i])) {
      if (index) *index = int(i);
      return f;
    }
  return nullptr;
}

TEST(ObstacleCourse, SameSeedSameTerrainOtherSeedOther) {
  const ProceduralTerrain a(makeObstacleCourse({.seed = 7}));
  const ProceduralTerrain b(makeObstacleCourse({.seed = 7}));
  const ProceduralTerrain c(makeObstacleCourse({.seed = 8}));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<> x(-19, 19), y(-9, 49);
  int differ = 0;
  for (int i = 0; i < 2000; ++i) {
    const double px = x(rng), py = y(rng);
    ASSERT_EQ(a.height(px, py), b.height(px, py));
    differ += a.height(px, py) != c.height(px, py);
  }
  EXPECT_GT(differ, 1900);
}

TEST(ObstacleCourse, FeaturesHaveTheirExactHeights) {
  const ProceduralTerrain t(makeObstacleCourse({.seed = 3}));
  const auto& d = t.description();
  int box_index = -1;
  const auto* box = findFeature<BoxObstacle>(d, &box_index);
  const auto* trench = findFeature<Trench>(d);
  const auto* ramp = findFeature<Ramp>(d);
  ASSERT_TRUE(box && trench && ramp);

  const auto& bf = box->footprint;
  EXPECT_DOUBLE_EQ(t.height(bf.cx, bf.cy), t.groundHeight(bf.cx, bf.cy) + 1.6);
  EXPECT_EQ(t.featureAt(bf.cx + 0.3, bf.cy - 0.3), box_index);  // flat top everywhere on it
  EXPECT_DOUBLE_EQ(t.height(bf.cx + 0.3, bf.cy - 0.3), t.height(bf.cx, bf.cy));

  const auto& tf = trench->footprint;
  EXPECT_DOUBLE_EQ(t.height(tf.cx, tf.cy), t.groundHeight(tf.cx, tf.cy) - 1.0);

  // Ramp: local x runs from the foot (-half_x) uphill; half way up the run it
  // has risen half the height above the ground at its foot.
  const auto& rf = ramp->footprint;
  const Eigen::Vector2d axis(std::cos(rf.yaw), std::sin(rf.yaw));
  const Eigen::Vector2d foot = Eigen::Vector2d(rf.cx, rf.cy) - rf.half_x * axis;
  const Eigen::Vector2d mid = foot + 0.5 * ramp->run * axis;
  const Eigen::Vector2d top = foot + (ramp->run + 0.5) * axis;
  const double ground_at_foot = t.groundHeight(foot.x(), foot.y());
  EXPECT_NEAR(t.height(mid.x(), mid.y()), ground_at_foot + 0.5 * ramp->height, 1e-12);
  EXPECT_NEAR(t.height(top.x(), top.y()), ground_at_foot + ramp->height, 1e-12);

  const auto* rock = findFeature<Rock>(d);
  ASSERT_TRUE(rock);
  const auto c = rock->shape.pose.translation();
  EXPECT_DOUBLE_EQ(*rock->shape.topHeight(c.x(), c.y()), c.z() + rock->shape.size.z());
}

TEST(ObstacleCourse, MaxHeightInBoundsEveryHeight) {
  const ProceduralTerrain t(makeObstacleCourse({.seed = 5}));
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<> x(-19, 17), y(-9, 47), u(0, 1);
  for (int b = 0; b < 300; ++b) {
    const double x0 = x(rng), y0 = y(rng), w = 0.1 + 2.5 * u(rng);
    const Box2 box{x0, y0, x0 + w, y0 + w};
    const double bound = t.maxHeightIn(box);
    for (int i = 0; i < 200; ++i)
      ASSERT_LE(t.height(x0 + w * u(rng), y0 + w * u(rng)), bound + 1e-12);
  }
}

TEST(Superquadric, SurfacePointsHaveFEqualOne) {
  Superquadric s;
  s.size = {0.3, 0.2, 0.1};
  s.eps1 = 0.5;
  s.eps2 = 0.8;
  s.pose = Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  auto spow = [](double v, double e) { return std::copysign(std::pow(std::abs(v), e), v); };
  for (double eta = -1.4; eta <= 1.4; eta += 0.2)
    for (double omega = -3.1; omega <= 3.1; omega += 0.3) {
      const Eigen::Vector3d local(
          s.size.x() * spow(std::cos(eta), s.eps1) * spow(std::cos(omega), s.eps2),
          s.size.y() * spow(std::cos(eta), s.eps1) * spow(std::sin(omega), s.eps2),
          s.size.z() * spow(std::sin(eta), s.eps1));
      EXPECT_NEAR(s.insideOutside(s.pose * local), 1.0, 1e-9);
    }
  EXPECT_LT(s.insideOutside(s.pose.translation()), 1.0);
  EXPECT_NEAR(*s.topHeight(1, 2), 3.1, 1e-12);
  EXPECT_FALSE(s.topHeight(1.5, 2.5).has_value());
}

TEST(HeightfieldTerrain, LoadsAndInterpolatesBilinearly) {
  TempDir dir;
  io::FloatImage h(3, 4);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) h(r, c) = float(r * 10 + c);
  io::writeTiff(dir / "dem.tif", h);
  std::ofstream(dir / "dem.json") << R"({"origin_x": 1.0, "origin_y": -2.0, "resolution": 0.5})";
  const auto t = loadHeightfield(dir / "dem.tif");
  // Cell (r, c) centre = (1 + (c + 0.5) * 0.5, -2 + (r + 0.5) * 0.5).
  EXPECT_DOUBLE_EQ(t.height(1.25, -1.75), 0.0);
  EXPECT_DOUBLE_EQ(t.height(1.25 + 3 * 0.5, -1.75 + 2 * 0.5), 23.0);
  EXPECT_DOUBLE_EQ(t.height(1.5, -1.5), 5.5);  // centre of four samples 0, 1, 10, 11
  EXPECT_TRUE(std::isnan(t.height(0.0, 0.0)));
  EXPECT_DOUBLE_EQ(t.maxHeightIn({1.25, -1.75, 1.6, -1.4}), 11.0);
}

// A scanner set over a terrain model's no-data is refused, not placed at NaN.
TEST(HeightfieldTerrain, AScannerOverNoDataIsRefused) {
  const GridSpec grid{-10.0, -10.0, 0.5, 40, 40};
  io::FloatImage h(40, 40, 1.0f);
  for (int r = 18; r < 22; ++r)
    for (int c = 18; c < 22; ++c) h(r, c) = NAN;
  const auto model = readScannerModel(findResource("config/scanner.json"));
  try {
    CourseScene scene(std::make_unique<HeightfieldTerrain>(h, grid), model);
    ADD_FAILURE() << "scanner placed at z " << scene.sensorPose().translation().z();
  } catch (const NoGroundError& e) {
    EXPECT_NE(std::string(e.what()).find("under the scanner at (0.00, 0.00) m"), std::string::npos)
        << e.what();
  }
  const CourseScene beside(std::make_unique<HeightfieldTerrain>(h, grid), model, {5.0, 5.0});
  EXPECT_NEAR(beside.roverGround().z(), 1.0, 1e-9);
  try {  // off the terrain: its extent, not a terrain model's no-data, is the reason
    CourseScene scene(std::make_unique<HeightfieldTerrain>(h, grid), model, {1e30, 0.0});
    ADD_FAILURE() << "scanner placed at z " << scene.sensorPose().translation().z();
  } catch (const NoGroundError& e) {
    EXPECT_NE(std::string(e.what()).find("at (1e+30, 0) m, where the rover starts: off the "
                                         "terrain, which spans x -9.75..9.75 m, y -9.75..9.75 m"),
              std::string::npos)
        << e.what();
  }
}

TEST(HeightfieldTerrain, BadSidecarIsNamed) {
  TempDir dir;
  io::writeTiff(dir / "dem.tif", io::FloatImage(3, 3, 1.0f));
  std::ofstream(dir / "dem.json") << R"({"origin_x": 1.0, "origin_y": -2.0, "resolution": -0.5})";
  try {
    loadHeightfield(dir / "dem.tif");
    FAIL();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("\"resolution\" must be positive"), std::string::npos);
  }
}

}  // namespace
}  // namespace ambler::sim

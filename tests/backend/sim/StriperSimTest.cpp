#include "sim/StriperSim.h"

#include <gtest/gtest.h>

#include "sim/ObstacleCourse.h"

namespace ambler::sim {
namespace {

struct Scene {
  ProceduralTerrain terrain;
  StriperScene striper;
};

Scene simulate(std::uint64_t seed, double noise) {
  ProceduralTerrain terrain(makeWorkArea({.seed = seed}));
  StriperModel model;
  model.noise_sigma = noise;
  auto striper = simulateStriper(terrain, model, seed);
  return {std::move(terrain), std::move(striper)};
}

TEST(StriperSim, PointsLieOnTheTerrainAndRocksOnTheirSuperquadric) {
  const auto s = simulate(3, 0.0);
  const auto& img = s.striper.image;
  const auto& features = s.terrain.description().features;
  ASSERT_GE(features.size(), 3u);
  int on_rocks = 0;
  for (int r = 0; r < img.rows(); ++r)
    for (int c = 0; c < img.cols(); ++c) {
      if (!img.hasPoint(r, c)) continue;
      const auto p = img.point(r, c);
      ASSERT_NEAR(p.z(), s.terrain.height(p.x(), p.y()), 1e-5);
      const int label = s.striper.labels(r, c);
      if (label == kLabelGround || label == kLabelNothing) continue;
      const auto& rock = std::get<Rock>(features[std::size_t(label - 1)]).shape;
      // Float storage of X, Y, Z limits how exactly F can be 1.
      EXPECT_NEAR(rock.insideOutside(p), 1.0, 2e-3);
      ++on_rocks;
    }
  EXPECT_GT(on_rocks, 500);
}

TEST(StriperSim, RangeShadowsFallBehindRocksAwayFromTheProjector) {
  const auto s = simulate(4, 0.0005);
  const auto& img = s.striper.image;
  const auto& features = s.terrain.description().features;
  int shadows = 0, behind_a_rock = 0;
  double lit_sand = 0, shadow_intensity = 0;
  int lit_sand_count = 0;
  for (int r = 0; r < img.rows(); ++r)
    for (int c = 0; c < img.cols(); ++c) {
      const int label = s.striper.labels(r, c);
      if (label == kLabelNothing) continue;
      const float intensity = img.intensity[img.index(r, c)];
      if (img.hasPoint(r, c)) {
        if (label == kLabelGround) lit_sand += intensity, ++lit_sand_count;
        continue;
      }
      ++shadows;
      shadow_intensity += intensity;
      // Where the camera ray met the ground, from the true surface.
      const Eigen::Vector3d eye = img.camera.center(), dir = img.camera.rayInWorld(r, c);
      double t = 0;
      while (eye.z() + t * dir.z() > s.terrain.height(eye.x() + t * dir.x(), eye.y() + t * dir.y()))
        t += 1e-4;
      const Eigen::Vector2d p = (eye + t * dir).head<2>();
      const Eigen::Vector2d away = (p - img.projector_position.head<2>()).normalized();
      for (const auto& f : features) {
        const auto& rock = std::get<Rock>(f).shape;
        const Eigen::Vector2d to_p = p - rock.pose.translation().head<2>();
        if (to_p.norm() < 2.5 * rock.footprintRadius() && to_p.dot(away) > 0) {
          ++behind_a_rock;
          break;
        }
      }
    }
  EXPECT_GT(shadows, 100);
  EXPECT_GE(behind_a_rock, 0.95 * shadows);
  EXPECT_LT(shadow_intensity / shadows, 0.5 * lit_sand / lit_sand_count);
}

}  // namespace
}  // namespace ambler::sim

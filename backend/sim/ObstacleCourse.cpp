#include "sim/ObstacleCourse.h"

#include <cmath>

#include "sim/RandomDraw.h"

namespace ambler::sim {

namespace {

// Places up to `count` rocks in `area` without overlapping `taken`; sizes in
// metres, burial as the fraction of a3 by which the centre sits below the
// ground.
void scatterRocks(RandomDraw& draw, const ProceduralTerrain& ground, const Box2& area, int count,
                  double a_lo, double a_hi, double a3_lo, double a3_hi, double burial_lo,
                  double burial_hi, std::vector<Box2>& taken, std::vector<Feature>& features) {
  for (int placed = 0, attempts = 0; placed < count && attempts < 50 * count; ++attempts) {
    Superquadric s;
    s.size = {draw(a_lo, a_hi), draw(a_lo, a_hi), draw(a3_lo, a3_hi)};
    s.eps1 = draw(0.4, 1.0);
    s.eps2 = draw(0.4, 1.0);
    const double x = draw(area.x_min, area.x_max), y = draw(area.y_min, area.y_max);
    const double r = s.footprintRadius();
    const Box2 b{x - r, y - r, x + r, y + r};
    if (overlapsAny(b, taken)) continue;
    // Burial: the share of the rock's height 2 a3 below the sand.
    const double z = ground.groundHeight(x, y) + (1 - 2 * draw(burial_lo, burial_hi)) * s.size.z();
    s.pose =
        Eigen::Translation3d(x, y, z) * Eigen::AngleAxisd(draw(0, M_PI), Eigen::Vector3d::UnitZ());
    features.push_back(Rock{s});
    taken.push_back(b);
    ++placed;
  }
}

}  // namespace

TerrainDescription makeObstacleCourse(const CourseOptions& options) {
  RandomDraw draw(options.seed);
  TerrainDescription d;
  d.extent = options.extent;
  d.waves = rollingGround(draw, 4, 0.03, 0.12, 4.0, 14.0);
  const ProceduralTerrain ground(d);  // rolling ground only, to seat features on

  std::vector<Box2> taken{{-3.0, -3.0, 3.0, 3.0}};  // keep the start area clear
  auto add = [&](Feature f, const Footprint& fp) {
    d.features.push_back(std::move(f));
    taken.push_back(fp.bounds());
  };
  if (options.obstacles) {
    const Footprint box{draw(-4, 4), draw(9, 13), draw(-0.3, 0.3), 0.7, 0.7};
    add(BoxObstacle{box, 1.6}, box);
    const Footprint trench{draw(-2, 2), draw(18, 22), draw(-0.1, 0.1), 4.0, 0.8};
    add(Trench{trench, 1.0}, trench);
    const Footprint ramp{draw(-3, 3), draw(28, 31), M_PI / 2 + draw(-0.2, 0.2), 3.0, 1.5};
    add(Ramp{ramp, 4.0, 0.8}, ramp);
  }
  const Box2 field{d.extent.x_min + 2, 4.0, d.extent.x_max - 2, d.extent.y_max - 4};
  scatterRocks(draw, ground, field, options.boulders, 0.4, 0.9, 0.3, 0.7, 0.5, 0.7, taken,
               d.features);
  scatterRocks(draw, ground, field, options.rocks, 0.05, 0.2, 0.04, 0.15, 0.5, 0.75, taken,
               d.features);
  return d;
}

CourseOptions longTraverse(std::uint64_t seed) {
  CourseOptions o;
  o.seed = seed;
  o.extent = {-20.0, -10.0, 20.0, 80.0};
  o.boulders = 12;  // 1.5 times the course's area
  o.rocks = 180;
  o.obstacles = false;
  return o;
}

TerrainDescription makeWorkArea(const WorkAreaOptions& options) {
  RandomDraw draw(options.seed);
  TerrainDescription d;
  const double h = options.size / 2;
  d.extent = {-h, -h, h, h};
  d.waves = rollingGround(draw, 3, 0.001, 0.004, 0.15, 0.5);
  const ProceduralTerrain ground(d);
  std::vector<Box2> taken;
  const Box2 field{-h + 0.12, -h + 0.12, h - 0.12, h - 0.12};
  scatterRocks(draw, ground, field, options.rocks, 0.03, 0.08, 0.025, 0.06, options.burial_min,
               options.burial_max, taken, d.features);
  return d;
}

}  // namespace ambler::sim

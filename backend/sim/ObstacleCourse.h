#pragma once

#include <cstdint>

#include "sim/ProceduralTerrain.h"

namespace ambler::sim {

// The walking course, after the high-bay of the cmu-1990 report: sandy
// rolling ground, a box too tall to step over, a 1 m deep trench, a ramp,
// boulders and scattered rocks. World frame: the rover starts at the origin
// facing +y, z up. The seed moves obstacles and draws the random parts.
struct CourseOptions {
  std::uint64_t seed = 1;
  Box2 extent{-20.0, -10.0, 20.0, 50.0};
  int boulders = 8;
  int rocks = 120;
  bool obstacles = true;  // box, trench and ramp
};
TerrainDescription makeObstacleCourse(const CourseOptions& options);

// A traverse for walks of a hundred steps and more: the course's rolling
// ground, boulders and rocks at the course's density, 90 m long, without
// the box, trench and ramp (which the gait planner does not yet cross on
// every seed).
CourseOptions longTraverse(std::uint64_t seed);

// The rock-sampling work area of the cmu-1990 sampling paper: a sand tray
// with small ripples and superquadric rocks in it, each with a share of its
// height (2 a3) below the sand drawn from [burial_min, burial_max]; by
// default from half (centre at the sand) to three quarters. The visible
// part is the true superquadric surface.
struct WorkAreaOptions {
  std::uint64_t seed = 1;
  double size = 1.2;  // side of the square tray [m], centred on the origin
  int rocks = 5;
  double burial_min = 0.5;
  double burial_max = 0.75;
};
TerrainDescription makeWorkArea(const WorkAreaOptions& options);

}  // namespace ambler::sim

#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sim/ProceduralTerrain.h"

namespace ambler::sim {

// Kinds of ground the perception is evaluated on, each drawn from a seed
// with exact heights. The obstacle course is the one the algorithms were
// first tuned on; the others test that they hold elsewhere.
enum class TerrainFamily {
  kCourse,
  kRockField,
  kCraterField,
  kRoughGround,
  kNegativeObstacles,
  kSlope
};

inline constexpr std::array kTerrainFamilies{
    TerrainFamily::kCourse,      TerrainFamily::kRockField,         TerrainFamily::kCraterField,
    TerrainFamily::kRoughGround, TerrainFamily::kNegativeObstacles, TerrainFamily::kSlope};

// Where a family's terrain has ground unless told otherwise: the rover
// starts at the origin facing +y.
inline constexpr Box2 kFamilyExtent{-20.0, -10.0, 20.0, 50.0};

// "course", "rocks", "craters", "rough", "negative", "slope".
std::string_view familyName(TerrainFamily family);
// What an operator reads: "course", "rock field", "crater field", "rough
// ground", "negative obstacles", "slope".
std::string_view familyTitle(TerrainFamily family);
std::optional<TerrainFamily> parseFamily(std::string_view name);
// Every family's name, for help and error texts: "course, rocks, craters,
// rough, negative or slope".
std::string familyNamesListed();

// Rocks whose sizes follow the Golombek & Rapp (1997) model for Mars: the
// cumulative fraction of area covered by rocks of diameter >= D is
// k exp(-q(k) D), q(k) = 1.79 + 0.152 / k, k the total rock abundance.
// Rocks stand about half their diameter above the ground.
struct RockFieldOptions {
  std::uint64_t seed = 1;
  Box2 extent = kFamilyExtent;
  double abundance = 0.1;     // k, the fraction of area covered by all rocks
  double d_min = 0.1;         // smaller rocks are left out [m]
  double d_max = 2.5;         // [m]
  double clear_radius = 1.5;  // no rock within this of the origin [m]
};
// Rocks per square metre with diameters in [d_lo, d_hi] under the model.
double golombekRappDensity(double abundance, double d_lo, double d_hi);
TerrainDescription makeRockField(const RockFieldOptions& options);

// Fresh craters with a power-law size-frequency distribution, cumulative
// N(>= D) = density_1m * D^-exponent per square metre (D in metres),
// depth/diameter near 0.2 and rims 0.04 D high, on gently rolling ground.
struct CraterFieldOptions {
  std::uint64_t seed = 1;
  Box2 extent = kFamilyExtent;
  double density_1m = 0.01;  // craters >= 1 m per square metre
  double exponent = 2.0;
  double d_min = 0.5;  // [m]
  double d_max = 12.0;
  double depth_ratio_min = 0.17, depth_ratio_max = 0.21;
  double clear_radius = 1.5;  // no crater rim within this of the origin [m]
};
TerrainDescription makeCraterField(const CraterFieldOptions& options);

// Fractional Brownian ground: random-phase sinusoids in random directions
// at wavelengths spaced evenly in log between wavelength_min and _max,
// amplitudes scaled so that the height difference between points one metre
// apart has standard deviation rms_1m and grows as lag^hurst.
struct RoughGroundOptions {
  std::uint64_t seed = 1;
  Box2 extent = kFamilyExtent;
  double hurst = 0.7;
  double rms_1m = 0.05;                                 // [m]
  double wavelength_min = 0.15, wavelength_max = 25.0;  // [m]
  int waves_per_octave = 4;
};
TerrainDescription makeRoughGround(const RoughGroundOptions& options);
// Expected std. dev. of z(p + lag) - z(p) over positions and directions.
double roughnessAt(const std::vector<Wave>& waves, double lag);

// Trenches (vertical walls), V-shaped ditches and steps down, of several
// widths, depths and orientations, on rolling ground, all ahead of the
// rover within 4-22 m.
struct NegativeObstacleOptions {
  std::uint64_t seed = 1;
  Box2 extent = kFamilyExtent;
  int trenches = 3;
  int ditches = 2;
  bool step = true;
};
TerrainDescription makeNegativeObstacles(const NegativeObstacleOptions& options);

// A plane of the given slope rising in direction `uphill` (radians from +x),
// with the course's rolling ground and scattered rocks on it.
struct SlopeOptions {
  std::uint64_t seed = 1;
  Box2 extent = kFamilyExtent;
  double slope_deg = 20.0;
  double uphill = M_PI / 2;
  int rocks = 120;
};
TerrainDescription makeSlope(const SlopeOptions& options);

// One terrain of a family: the seed draws the family's parameters over
// their stated ranges (rock abundance 5-30 %, crater density, Hurst
// exponent 0.5-0.9, slope 10-30 degrees in any direction, ...) and then the
// terrain, which has ground over `extent`.
TerrainDescription makeFamilyTerrain(TerrainFamily family, std::uint64_t seed,
                                     const Box2& extent = kFamilyExtent);

// Seeds on which the perception's parameters may be tuned, and the disjoint
// seeds on which it is evaluated and reported.
inline constexpr std::array<std::uint64_t, 3> kTuningSeeds{1, 2, 3};
inline constexpr std::array<std::uint64_t, 3> kEvaluationSeeds{1001, 1002, 1003};

}  // namespace ambler::sim

#include "sim/TerrainFamilies.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "sim/ObstacleCourse.h"
#include "sim/RandomDraw.h"

namespace ambler::sim {

namespace {

// Gentle rolling ground under a family's features: wavelengths 5-15 m.
std::vector<Wave> gentleWaves(RandomDraw& draw, int count, double amp_hi) {
  return rollingGround(draw, count, 0.3 * amp_hi, amp_hi, 5.0, 15.0);
}

double area(const Box2& b) { return b.width() * b.height(); }

// Golombek & Rapp: number of rocks per square metre and unit diameter.
double rocksPerDiameter(double k, double d) {
  const double q = 1.79 + 0.152 / k;
  return 4 * k * q * std::exp(-q * d) / (M_PI * d * d);
}

constexpr int kDiameterSteps = 2000;

// Diameters spaced evenly in log over [lo, hi] and the cumulative number
// density up to each (trapezoids in log d).
struct DiameterTable {
  std::vector<double> d, cumulative;
};

DiameterTable diameterTable(double k, double lo, double hi) {
  DiameterTable t;
  const double step = std::log(hi / lo) / kDiameterSteps;
  double sum = 0.0, prev = rocksPerDiameter(k, lo) * lo;
  for (int i = 0; i <= kDiameterSteps; ++i) {
    const double d = lo * std::exp(i * step);
    const double f = rocksPerDiameter(k, d) * d;  // per unit log d
    if (i > 0) sum += 0.5 * (f + prev) * step;
    prev = f;
    t.d.push_back(d);
    t.cumulative.push_back(sum);
  }
  return t;
}

double sampleDiameter(const DiameterTable& t, double u) {
  const double target = u * t.cumulative.back();
  const auto it = std::lower_bound(t.cumulative.begin(), t.cumulative.end(), target);
  const auto i = std::size_t(std::clamp<long>(it - t.cumulative.begin(), 1, kDiameterSteps));
  const double span = t.cumulative[i] - t.cumulative[i - 1];
  const double f = span > 0 ? (target - t.cumulative[i - 1]) / span : 0.0;
  return t.d[i - 1] + f * (t.d[i] - t.d[i - 1]);
}

// Each family's name on command lines and in JSON, and what an operator
// reads, in kTerrainFamilies' order.
struct FamilyNames {
  std::string_view name, title;
};
constexpr std::array<FamilyNames, kTerrainFamilies.size()> kFamilyNames{
    {{"course", "course"},
     {"rocks", "rock field"},
     {"craters", "crater field"},
     {"rough", "rough ground"},
     {"negative", "negative obstacles"},
     {"slope", "slope"}}};
static_assert(
    [] {
      for (std::size_t i = 0; i < kTerrainFamilies.size(); ++i)
        if (std::size_t(kTerrainFamilies[i]) != i) return false;
      return true;
    }(),
    "kFamilyNames is indexed by the family's value");

}  // namespace

std::string_view familyName(TerrainFamily family) { return kFamilyNames[std::size_t(family)].name; }

std::string_view familyTitle(TerrainFamily family) {
  return kFamilyNames[std::size_t(family)].title;
}

std::optional<TerrainFamily> parseFamily(std::string_view name) {
  for (const auto f : kTerrainFamilies)
    if (familyName(f) == name) return f;
  return std::nullopt;
}

std::string familyNamesListed() {
  std::string names;
  for (std::size_t i = 0; i < kTerrainFamilies.size(); ++i) {
    if (i > 0) names += i + 1 == kTerrainFamilies.size() ? " or " : ", ";
    names += familyName(kTerrainFamilies[i]);
  }
  return names;
}

double golombekRappDensity(double abundance, double d_lo, double d_hi) {
  return diameterTable(abundance, d_lo, d_hi).cumulative.back();
}

TerrainDescription makeRockField(const RockFieldOptions& o) {
  RandomDraw draw(o.seed);
  TerrainDescription d;
  d.extent = o.extent;
  d.waves = gentleWaves(draw, 3, 0.05);
  const ProceduralTerrain ground(d);
  const auto table = diameterTable(o.abundance, o.d_min, o.d_max);
  const long count = draw.poisson(area(o.extent) * table.cumulative.back());
  for (long i = 0; i < count; ++i) {
    const double diameter = sampleDiameter(table, draw(0, 1));
    const double x = draw(o.extent.x_min, o.extent.x_max);
    const double y = draw(o.extent.y_min, o.extent.y_max);
    // Drawn whether or not the rock is kept, so that the clear area does
    // not change the rest of the field.
    const double elongation = draw(0.8, 1.25), visible = diameter * draw(0.35, 0.6);
    const double burial = draw(0.5, 0.7), eps1 = draw(0.4, 1.0), eps2 = draw(0.4, 1.0);
    const double turn = draw(0, M_PI);
    if (std::hypot(x, y) < o.clear_radius + diameter) continue;
    Superquadric s;
    s.size = {0.5 * diameter * elongation, 0.5 * diameter / elongation,
              visible / (2 * (1 - burial))};
    s.eps1 = eps1;
    s.eps2 = eps2;
    const double z = ground.groundHeight(x, y) + (1 - 2 * burial) * s.size.z();
    s.pose = Eigen::Translation3d(x, y, z) * Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ());
    d.features.push_back(Rock{s});
  }
  return d;
}

TerrainDescription makeCraterField(const CraterFieldOptions& o) {
  RandomDraw draw(o.seed);
  TerrainDescription d;
  d.extent = o.extent;
  d.waves = gentleWaves(draw, 3, 0.04);
  const double lo = std::pow(o.d_min, -o.exponent), hi = std::pow(o.d_max, -o.exponent);
  const long count = draw.poisson(area(o.extent) * o.density_1m * (lo - hi));
  for (long i = 0; i < count; ++i) {
    // Inverse of the truncated power law's cumulative distribution.
    const double diameter = std::pow(lo - draw(0, 1) * (lo - hi), -1.0 / o.exponent);
    const double x = draw(o.extent.x_min, o.extent.x_max);
    const double y = draw(o.extent.y_min, o.extent.y_max);
    const double ratio = draw(o.depth_ratio_min, o.depth_ratio_max);
    if (std::hypot(x, y) < o.clear_radius + 0.6 * diameter) continue;
    d.craters.push_back({x, y, diameter, ratio * diameter, 0.04 * diameter});
  }
  return d;
}

double roughnessAt(const std::vector<Wave>& waves, double lag) {
  double var = 0.0;
  for (const auto& w : waves)
    var += w.amplitude * w.amplitude * (1 - std::cyl_bessel_j(0.0, std::hypot(w.kx, w.ky) * lag));
  return std::sqrt(var);
}

TerrainDescription makeRoughGround(const RoughGroundOptions& o) {
  RandomDraw draw(o.seed);
  TerrainDescription d;
  d.extent = o.extent;
  const double octaves = std::log2(o.wavelength_max / o.wavelength_min);
  const int count = std::max(2, int(std::ceil(octaves * o.waves_per_octave)));
  for (int i = 0; i < count; ++i) {
    const double wavelength =
        o.wavelength_min * std::pow(o.wavelength_max / o.wavelength_min, double(i) / (count - 1));
    const double k = 2 * M_PI / wavelength, dir = draw(0, 2 * M_PI);
    // Power per log wavenumber ~ k^-2H gives a structure function ~ lag^2H.
    d.waves.push_back(
        {std::pow(wavelength, o.hurst), k * std::cos(dir), k * std::sin(dir), draw(0, 2 * M_PI)});
  }
  const double scale = o.rms_1m / roughnessAt(d.waves, 1.0);
  for (auto& w : d.waves) w.amplitude *= scale;
  return d;
}

TerrainDescription makeNegativeObstacles(const NegativeObstacleOptions& o) {
  RandomDraw draw(o.seed);
  TerrainDescription d;
  d.extent = o.extent;
  d.waves = gentleWaves(draw, 3, 0.04);
  std::vector<Box2> taken{{-3.0, -3.0, 3.0, 3.0}};
  auto place = [&](int count, bool ditch) {
    for (int placed = 0, attempts = 0; placed < count && attempts < 200; ++attempts) {
      const double half_y = 0.5 * draw(0.3, 1.5);
      const Footprint fp{draw(-8, 8), draw(5, 20), draw(0, M_PI), 0.5 * draw(2.0, 8.0), half_y};
      const double depth = draw(0.2, 1.0);
      const auto b = fp.bounds();
      if (overlapsAny(b, taken, 1.0)) continue;
      d.features.push_back(Trench{fp, depth, ditch ? half_y : 0.0});
      taken.push_back(b);
      ++placed;
    }
  };
  place(o.trenches, false);
  place(o.ditches, true);
  if (o.step) {
    // A drop across the whole field beyond a line 21-24 m ahead: a trench
    // whose footprint reaches past the extent.
    const double yaw = draw(-0.5, 0.5), ahead = draw(21, 24), depth = draw(0.3, 0.6);
    const Eigen::Vector2d normal(-std::sin(yaw), std::cos(yaw));
    const Eigen::Vector2d centre = Eigen::Vector2d(0, ahead) + 100 * normal;
    d.features.push_back(Trench{{centre.x(), centre.y(), yaw, 200.0, 100.0}, depth, 0.0});
  }
  return d;
}

TerrainDescription makeSlope(const SlopeOptions& o) {
  CourseOptions course;
  course.seed = o.seed;
  course.extent = o.extent;
  course.rocks = o.rocks;
  course.obstacles = false;
  auto d = makeObstacleCourse(course);
  const double g = std::tan(o.slope_deg * M_PI / 180.0);
  d.gradient = {g * std::cos(o.uphill), g * std::sin(o.uphill)};
  for (auto& f : d.features)
    if (auto* rock = std::get_if<Rock>(&f)) {
      auto& pose = rock->shape.pose;
      pose.translation().z() += d.gradient.dot(pose.translation().head<2>());
    }
  return d;
}

TerrainDescription makeFamilyTerrain(TerrainFamily family, std::uint64_t seed, const Box2& extent) {
  // Parameters from their own stream, so that the terrain's draws do not
  // depend on how many parameters a family has.
  RandomDraw draw(seed * 7919 + std::uint64_t(family));
  switch (family) {
    case TerrainFamily::kCourse:
      return makeObstacleCourse({.seed = seed, .extent = extent});
    case TerrainFamily::kRockField:
      return makeRockField({.seed = seed, .extent = extent, .abundance = draw(0.05, 0.30)});
    case TerrainFamily::kCraterField:
      return makeCraterField({.seed = seed, .extent = extent, .density_1m = draw(0.005, 0.02)});
    case TerrainFamily::kRoughGround:
      return makeRoughGround(
          {.seed = seed, .extent = extent, .hurst = draw(0.5, 0.9), .rms_1m = draw(0.02, 0.08)});
    case TerrainFamily::kNegativeObstacles:
      return makeNegativeObstacles({.seed = seed, .extent = extent});
    case TerrainFamily::kSlope:
      return makeSlope(
          {.seed = seed, .extent = extent, .slope_deg = draw(10, 30), .uphill = draw(0, 2 * M_PI)});
  }
  return makeObstacleCourse({.seed = seed, .extent = extent});
}

}  // namespace ambler::sim

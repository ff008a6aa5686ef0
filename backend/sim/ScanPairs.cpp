#include "sim/ScanPairs.h"

#include <cmath>

#include "core/Angles.h"
#include "sim/CourseScene.h"
#include "sim/RandomDraw.h"

namespace ambler::sim {

namespace {

// The scan's points levelled about its sensor, and that frame in the world.
struct Levelled {
  std::vector<Eigen::Vector3d> points;
  Eigen::Isometry3d to_world = Eigen::Isometry3d::Identity();
};

Levelled scanOf(TerrainDescription terrain, const ScannerModel& scanner, const Eigen::Vector2d& xy,
                double heading, std::uint64_t noise_seed) {
  const CourseScene scene(std::move(terrain), scanner, xy, heading);
  const auto image = scene.scan(noise_seed);
  const Eigen::Isometry3d& sensor = image.sensor_to_world;
  Levelled out;
  out.to_world.translation() = sensor.translation();
  out.to_world.linear() =
      Eigen::AngleAxisd(std::atan2(sensor(1, 0), sensor(0, 0)), Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const Eigen::Matrix3d level = out.to_world.linear().transpose() * sensor.linear();
  for (const auto& p : image.pointsInSensor()) out.points.push_back(level * p);
  return out;
}

}  // namespace

ScanPair makeScanPair(TerrainFamily family, std::uint64_t seed, const ScannerModel& scanner,
                      const ScanPairOptions& o) {
  RandomDraw draw(seed * 104729 + 17 * std::uint64_t(family) + (o.foreign ? 1 : 0));
  ScanPair pair;
  pair.family = family;
  pair.seed = seed;
  pair.foreign = o.foreign;
  // The target's rover near the terrain's origin, looking roughly along +y
  // where every family has its features; the source's within a circle
  // around it, turned either way.
  const Eigen::Vector2d at(draw(-3, 3), draw(-2, 4));
  const double heading = draw(-45, 45) * kDeg;
  pair.distance_m = draw(o.min_distance_m, o.max_distance_m);
  const double bearing = heading + draw(-90, 90) * kDeg;
  pair.turn_deg = draw(o.min_turn_deg, o.max_turn_deg) * (draw(0, 1) < 0.5 ? -1 : 1);
  const Eigen::Vector2d from =
      at + pair.distance_m * Eigen::Vector2d(-std::sin(bearing), std::cos(bearing));
  auto model = scanner;
  model.range_sigma_k = pair.noise_k =
      o.noise_k[std::size_t(draw(0, 1) * double(o.noise_k.size())) % o.noise_k.size()];
  const auto target = scanOf(makeFamilyTerrain(family, seed), model, at, heading, seed * 2 + 1);
  const auto source = scanOf(makeFamilyTerrain(family, o.foreign ? seed + 500 : seed), model, from,
                             heading + pair.turn_deg * kDeg, seed * 2 + 2);
  pair.target = target.points, pair.target_to_world = target.to_world;
  pair.source = source.points, pair.source_to_world = source.to_world;
  // The guess's error: a shift and a turn about random axes, each up to
  // its limit.
  auto direction = [&] {
    const double z = draw(-1, 1), phi = draw(0, 2 * M_PI), r = std::sqrt(1 - z * z);
    return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
  };
  pair.error_m = draw(0, o.max_error_m);
  pair.error_deg = draw(0, o.max_error_deg);
  pair.error = Eigen::Translation3d(pair.error_m * direction()) *
               Eigen::AngleAxisd(pair.error_deg * kDeg, direction());
  return pair;
}

}  // namespace ambler::sim

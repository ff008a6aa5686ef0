#include "sim/RoverWorld.h"

#include "gait/GaitPlanner.h"
#include "sim/ObstacleCourse.h"

namespace ambler::sim {

namespace {

// The scanner's view of the course: the exact terrain sampled every 2 cm
// over the area (plus the scanner's reach) and interpolated, so a simulated
// scan costs the rover little next to the ground station's work (the
// rover's own feet still meet the exact terrain).
HeightfieldTerrain sampledCourse(const Terrain& terrain, const Box2& area) {
  const Box2 reach{area.x_min - 5, area.y_min - 5, area.x_max + 5, area.y_max + 12};
  const GridSpec grid = GridSpec::covering(reach, 0.02);
  return HeightfieldTerrain(sampleHeights(terrain, grid), grid);
}

ExecutionNoise seeded(ExecutionNoise n, std::uint64_t seed) {
  n.seed = n.seed * 1000003 + seed;
  return n;
}

}  // namespace

RoverWorld::RoverWorld(std::uint64_t seed, const gait::RoverModel& model,
                       const gait::GaitOptions& gait, ExecutionNoise noise, ScannerModel scanner,
                       const Box2& scanned_area)
    : seed_(seed),
      model_(model),
      scanner_(std::move(scanner)),
      terrain_(makeObstacleCourse({.seed = seed})),
      seen_(sampledCourse(terrain_, scanned_area)),
      caster_(seen_, {.cell_size = 0.25, .step = 0.1, .tolerance = 1e-3}),
      rover_(terrain_, model, seeded(noise, seed),
             settleOnTerrain(gait::nominalStance({}, model, gait), terrain_, model)) {}

sensor::RangeImage RoverWorld::scan(std::uint64_t index) const {
  return simulateScan(caster_, scanner_, mountPose(rover_.truth().body), seed_ * 1000 + index);
}

Eigen::Isometry3d RoverWorld::mountPose(const gait::BodyPose& b) const {
  const double ground_z = b.link_z - model_.link_plane_nominal_m;
  return scanner_.mountPose({b.xy.x(), b.xy.y(), ground_z}, b.heading_rad);
}

}  // namespace ambler::sim

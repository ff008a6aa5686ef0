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

RoverWorld::RoverWorld(const CourseOptions& course, const gait::RoverModel& model,
                       const gait::GaitOptions& gait, ExecutionNoise noise, ScannerModel scanner,
                       const Box2& scanned_area)
    : RoverWorld(std::make_unique<ProceduralTerrain>(makeObstacleCourse(course)), course.seed,
                 model, gait, noise, std::move(scanner), scanned_area) {}

RoverWorld::RoverWorld(std::unique_ptr<const Terrain> terrain, std::uint64_t seed,
                       const gait::RoverModel& model, const gait::GaitOptions& gait,
                       ExecutionNoise noise, ScannerModel scanner, const Box2& scanned_area)
    : seed_(seed),
      model_(model),
      scanner_(std::move(scanner)),
      terrain_(std::move(terrain)),
      course_(dynamic_cast<const ProceduralTerrain*>(terrain_.get())),
      seen_(sampledCourse(*terrain_, scanned_area)),
      caster_(seen_, {.cell_size = 0.25, .step = 0.1, .tolerance = 1e-3}),
      rover_(*terrain_, model, seeded(noise, seed),
             settleOnTerrain(gait::nominalStance({}, model, gait), *terrain_, model)) {}

sensor::RangeImage RoverWorld::scan(std::uint64_t index) const {
  return simulateScan(caster_, scanner_, mountPose(rover_.truth().body), seed_ * 1000 + index);
}

sensor::StriperImage RoverWorld::striperScan(std::uint64_t index) const {
  if (!striper_)
    striper_ = std::make_unique<StriperRenderer>(
        *course_, RayCasterOptions{.cell_size = 0.25, .step = 0.01, .tolerance = 1e-4});
  const gait::BodyPose& b = rover_.truth().body;
  const auto at = [&](double right, double forward, double up) {
    const Eigen::Vector2d xy = b.toWorld(Eigen::Vector2d(right, forward));
    return Eigen::Vector3d(xy.x(), xy.y(), terrain_->height(xy.x(), xy.y()) + up);
  };
  // Body frame: x right, y forward. The camera looks down from 1.1 m at the
  // ground 2.6 m ahead of the body's centre; the projector sits beside it.
  StriperModel model;
  model.camera_position = at(0.0, 2.0, 1.1);
  model.look_at = at(0.0, 2.6, 0.0);
  model.projector_position = at(0.5, 2.1, 0.8);
  return striper_->render(model, seed_ * 1000 + index).image;
}

Eigen::Isometry3d RoverWorld::mountPose(const gait::BodyPose& b) const {
  const double ground_z = b.link_z - model_.link_plane_nominal_m;
  return scanner_.mountPose({b.xy.x(), b.xy.y(), ground_z}, b.heading_rad);
}

}  // namespace ambler::sim

#pragma once

#include <cstdint>
#include <memory>

#include "sim/ObstacleCourse.h"
#include "sim/RayCaster.h"
#include "sim/ScannerSim.h"

namespace ambler::sim {

// A procedural terrain (by default the obstacle course of one seed) with the rover standing on it
// and its scanner mounted: what every simulated scan needs (terrain, ray caster, sensor pose).
// Holds references between its parts, so it does not move. Each constructor
// throws NoGroundError when the terrain has no height under the rover.
class CourseScene {
 public:
  CourseScene(std::uint64_t seed, ScannerModel model, Eigen::Vector2d rover_xy = {0.0, 0.0},
              double heading = 0.0);
  // Any procedural terrain in place of the course.
  CourseScene(TerrainDescription terrain, ScannerModel model, Eigen::Vector2d rover_xy = {0.0, 0.0},
              double heading = 0.0);
  // Any terrain at all (a DTM's, say).
  CourseScene(std::unique_ptr<const Terrain> terrain, ScannerModel model,
              Eigen::Vector2d rover_xy = {0.0, 0.0}, double heading = 0.0);
  CourseScene(const CourseScene&) = delete;
  CourseScene& operator=(const CourseScene&) = delete;

  const Terrain& terrain() const { return *terrain_; }
  const RayCaster& caster() const { return caster_; }
  const ScannerModel& model() const { return model_; }
  // The ground point under the rover and the scanner's pose in the world.
  const Eigen::Vector3d& roverGround() const { return rover_; }
  const Eigen::Isometry3d& sensorPose() const { return pose_; }

  sensor::RangeImage scan(std::uint64_t noise_seed) const;
  // Truth from the EmbreeCaster at 2 cm, independent of the scans' caster.
  VisibilityTruth truth(const GridSpec& grid) const;
  // The scan's footprint on the horizontal plane through the rover's ground.
  Box2 footprint() const;

 private:
  std::unique_ptr<const Terrain> terrain_;
  RayCaster caster_;
  ScannerModel model_;
  Eigen::Vector3d rover_;
  Eigen::Isometry3d pose_;
};

}  // namespace ambler::sim

#pragma once

// The simulated Ambler in its world: the obstacle course of one seed or a
// real terrain model, what its scanner sees of it, and the rover executing
// moves on it. The
// autonomous walk and the simulated rover behind a link share it.

#include <cstdint>
#include <memory>

#include "core/GridSpec.h"
#include "gait/GaitPlanner.h"
#include "sim/HeightfieldTerrain.h"
#include "sim/ObstacleCourse.h"
#include "sim/ProceduralTerrain.h"
#include "sim/RayCaster.h"
#include "sim/RoverSim.h"
#include "sim/ScannerSim.h"
#include "sim/StriperSim.h"

namespace ambler::sim {

class RoverWorld {
 public:
  // The course, the rover standing in its nominal stance at the start; the
  // course's seed also draws the execution noise; `scanned_area` is where
  // scans need the terrain (the scanner's reach beyond it is added).
  RoverWorld(const CourseOptions& course, const gait::RoverModel& model,
             const gait::GaitOptions& gait, ExecutionNoise noise, ScannerModel scanner,
             const Box2& scanned_area);
  // Any terrain (a DTM's, say), the rover at its origin facing +y; `seed`
  // draws the execution and scan noise. Throws NoGroundError when a foot of
  // the start has no ground under it.
  RoverWorld(std::unique_ptr<const Terrain> terrain, std::uint64_t seed,
             const gait::RoverModel& model, const gait::GaitOptions& gait, ExecutionNoise noise,
             ScannerModel scanner, const Box2& scanned_area);
  RoverWorld(const RoverWorld&) = delete;
  RoverWorld& operator=(const RoverWorld&) = delete;

  RoverSim& rover() { return rover_; }
  const RoverSim& rover() const { return rover_; }
  const Terrain& terrain() const { return *terrain_; }
  // The light striper renders procedural courses only (rocks apart from
  // the ground).
  bool hasStriper() const { return course_ != nullptr; }
  const ScannerModel& scanner() const { return scanner_; }

  // A range image from where the rover really is, tagged with that pose;
  // `index` varies the noise from scan to scan.
  sensor::RangeImage scan(std::uint64_t index) const;
  // A light-striper image of the ground just ahead of the body, from a
  // striper mounted at the body's front (assumed mount: the cmu-1990
  // sampling work used a separate testbed). The first call builds a fine
  // ray caster over the exact course. Only when hasStriper().
  sensor::StriperImage striperScan(std::uint64_t index) const;
  // The scanner's pose for a body pose (the mount is above the ground
  // under the body).
  Eigen::Isometry3d mountPose(const gait::BodyPose& body) const;

 private:
  std::uint64_t seed_;
  gait::RoverModel model_;
  ScannerModel scanner_;
  std::unique_ptr<const Terrain> terrain_;
  const ProceduralTerrain* course_ = nullptr;  // terrain_ when it is a course
  HeightfieldTerrain seen_;                    // what the scanner's rays meet
  RayCaster caster_;
  mutable std::unique_ptr<StriperRenderer> striper_;  // built when first needed
  RoverSim rover_;
};

}  // namespace ambler::sim

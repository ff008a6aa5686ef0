#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "rover/SimulatedRover.h"
#include "sim/CourseScene.h"
#include "sim/HeightfieldTerrain.h"
#include "sim/TerrainFamilies.h"

namespace ambler::rover {

// What the simulated rover stands on (ambler-gs's built-in simulator,
// ambler-sim): a real terrain model, or ground of a terrain family drawn
// from the course seed (the obstacle course by default), so that an
// operator can watch a walk on the ground the evaluations score.
struct SimulatedGround {
  std::optional<sim::DtmSource> dtm;
  sim::TerrainFamily family = sim::TerrainFamily::kCourse;

  // The scene a single scan of `seed` is taken in.
  sim::CourseScene scene(std::uint64_t seed, const sim::ScannerModel& model) const;
  // The simulated rover's ground for `seed` (options.course.seed is set).
  void applyTo(std::uint64_t seed, SimulatedRoverOptions& options) const;
  // "course 3", "rock field 3", "terrain model x.tif".
  std::string name(std::uint64_t seed) const;
};

}  // namespace ambler::rover

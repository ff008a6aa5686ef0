#include "rover/SimulatedGround.h"

#include <memory>

namespace ambler::rover {

sim::CourseScene SimulatedGround::scene(std::uint64_t seed, const sim::ScannerModel& model) const {
  if (dtm)
    return sim::CourseScene(std::make_unique<sim::HeightfieldTerrain>(sim::loadDtm(*dtm)), model);
  if (family != sim::TerrainFamily::kCourse)
    return sim::CourseScene(sim::makeFamilyTerrain(family, seed), model);
  return sim::CourseScene(seed, model);
}

void SimulatedGround::applyTo(std::uint64_t seed, SimulatedRoverOptions& options) const {
  options.course.seed = seed;
  options.dtm = dtm;
  if (!dtm && family != sim::TerrainFamily::kCourse)
    options.terrain = sim::makeFamilyTerrain(family, seed);
}

std::string SimulatedGround::name(std::uint64_t seed) const {
  if (dtm) return "terrain model " + dtm->path.filename().string();
  return std::string(sim::familyTitle(family)) + " " + std::to_string(seed);
}

}  // namespace ambler::rover

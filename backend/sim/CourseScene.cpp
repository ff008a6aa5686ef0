#include "sim/CourseScene.h"

#include <cmath>

#include "sim/EmbreeCaster.h"

namespace ambler::sim {

CourseScene::CourseScene(std::uint64_t seed, ScannerModel model, Eigen::Vector2d rover_xy,
                         double heading)
    : CourseScene(makeObstacleCourse({.seed = seed}), std::move(model), rover_xy, heading) {}

CourseScene::CourseScene(TerrainDescription terrain, ScannerModel model, Eigen::Vector2d rover_xy,
                         double heading)
    : CourseScene(std::make_unique<ProceduralTerrain>(std::move(terrain)), std::move(model),
                  rover_xy, heading) {}

CourseScene::CourseScene(std::unique_ptr<const Terrain> terrain, ScannerModel model,
                         Eigen::Vector2d rover_xy, double heading)
    : terrain_(std::move(terrain)),
      caster_(*terrain_),
      model_(std::move(model)),
      rover_(rover_xy.x(), rover_xy.y(), terrain_->height(rover_xy.x(), rover_xy.y())),
      pose_(model_.mountPose(rover_, heading)) {
  if (!std::isfinite(rover_.z())) throw noGroundAtStart("the scanner", rover_.head<2>(), *terrain_);
}

sensor::RangeImage CourseScene::scan(std::uint64_t noise_seed) const {
  return simulateScan(caster_, model_, pose_, noise_seed);
}

VisibilityTruth CourseScene::truth(const GridSpec& grid) const {
  // Occluders lie between the sensor and the grid.
  const Box2 g = grid.bounds();
  const auto s = pose_.translation();
  const Box2 area{std::min(g.x_min, s.x()) - 1, std::min(g.y_min, s.y()) - 1,
                  std::max(g.x_max, s.x()) + 1, std::max(g.y_max, s.y()) + 1};
  const EmbreeCaster independent(*terrain_, area);
  return computeVisibility(independent, model_, pose_, grid);
}

Box2 CourseScene::footprint() const { return groundFootprint(model_, pose_, rover_.z()); }

}  // namespace ambler::sim

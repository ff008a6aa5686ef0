#pragma once

#include <memory>

#include "sim/RayCaster.h"

namespace ambler::sim {

// A second, independent ray caster for ground truth: the terrain sampled on
// a lattice of `spacing` over `area` (clipped to the terrain's extent) and
// handed to Intel Embree as a triangulated grid. Unlike RayCaster it
// neither marches nor bisects, and shares no code with it. Vertical walls
// become slopes one lattice step wide; lattice cells with a hole in the
// terrain are left out. Thread-safe.
class EmbreeCaster final : public FirstHit {
 public:
  EmbreeCaster(const Terrain& terrain, const Box2& area, double spacing = 0.02);
  ~EmbreeCaster() override;
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;

  std::optional<double> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double max_range) const override;
  const Terrain& terrain() const override { return terrain_; }

 private:
  struct Scene;
  const Terrain& terrain_;
  std::unique_ptr<Scene> scene_;
};

}  // namespace ambler::sim

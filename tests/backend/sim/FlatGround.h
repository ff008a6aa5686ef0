#pragma once

#include <utility>
#include <vector>

#include "sim/ProceduralTerrain.h"

namespace ambler::sim {

// Level ground at z = 0 over +-100 m, with `features` on it.
inline ProceduralTerrain flatGround(std::vector<Feature> features = {}) {
  TerrainDescription d;
  d.extent = {-100, -100, 100, 100};
  d.features = std::move(features);
  return ProceduralTerrain(std::move(d));
}

}  // namespace ambler::sim

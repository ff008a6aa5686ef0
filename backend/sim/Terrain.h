#pragma once

#include "core/GridSpec.h"

namespace ambler::sim {

// The ground the simulator's sensors look at: a height function z(x, y) in
// the world frame (z up) over a rectangular extent.
class Terrain {
 public:
  virtual ~Terrain() = default;

  // Exact ground height [m]; NaN outside extent().
  virtual double height(double x, double y) const = 0;

  // An upper bound of height() over `box` (need not be tight). The ray
  // caster skips space above it.
  virtual double maxHeightIn(const Box2& box) const = 0;

  virtual Box2 extent() const = 0;
};

}  // namespace ambler::sim

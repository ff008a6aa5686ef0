#pragma once

#include <Eigen/Core>
#include <vector>

#include "gait/Stance.h"

namespace ambler::widgets {

// The rover as the views draw it: a stance and the conservative support
// polygon of its supporting feet, worked out by whoever hands it over.
struct RoverDisplay {
  gait::Stance stance;
  std::vector<Eigen::Vector2d> support_polygon;
};

}  // namespace ambler::widgets

#pragma once

#include <Eigen/Core>
#include <string>

#include "core/Superquadric.h"
#include "sensor/StriperImage.h"

namespace ambler::sampling {

// The clam-shell gripper of the cmu-1990 sampling testbed: two
// hemispherical jaws. The paper gives no dimensions; these are assumed.
struct Gripper {
  double max_opening_m = 0.20;  // between the open jaws' rims
  double clearance_m = 0.02;    // added to the rock's extent on each side
};

// cmu-1990 sampling paper §6, spherical grasping: the gripper's centre over
// the rock's centre of mass (a superquadric's centre), the jaws parallel to
// its main axis (they close across it), lowered until they touch the
// terrain around the rock.
struct GraspPlan {
  bool ok = false;
  std::string reason;               // why not, when not ok
  Eigen::Vector3d centre{0, 0, 0};  // x, y of the rock; z where the jaws touch the terrain
  double yaw_rad = 0.0;             // of the main axis, from world x
  double opening_m = 0.0;
};

// The terrain height is the median of the measured points in a ring from
// 1.3 to 2 footprint radii around the rock; without such points, the
// lowest point of the fitted rock.
GraspPlan planGrasp(const Superquadric& rock, const sensor::StriperImage& image,
                    const Gripper& gripper = {});

}  // namespace ambler::sampling

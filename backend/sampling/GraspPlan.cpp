#include "sampling/GraspPlan.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace ambler::sampling {

GraspPlan planGrasp(const Superquadric& rock, const sensor::StriperImage& image,
                    const Gripper& gripper) {
  GraspPlan plan;
  const Eigen::Vector3d centre = rock.pose.translation();
  if (!centre.allFinite() || !rock.size.allFinite()) {
    plan.reason = "the rock's fit is not finite";
    return plan;
  }
  // The main axis: the fitted axis that spans most of the ground (a fit may
  // put any of its axes upright).
  const Eigen::Matrix3d axes = rock.pose.linear();
  int main = 0;
  for (int i = 1; i < 3; ++i)
    if (rock.size[i] * axes.col(i).head<2>().norm() >
        rock.size[main] * axes.col(main).head<2>().norm())
      main = i;
  const Eigen::Vector2d along = axes.col(main).head<2>().normalized();
  plan.yaw_rad = std::atan2(along.y(), along.x());
  // Horizontal extents along and across it.
  auto extent = [&](const Eigen::Vector2d& u) { return 2 * rock.reach({u.x(), u.y(), 0.0}); };
  const double width = std::max(extent(along), extent({-along.y(), along.x()}));
  plan.opening_m = width + 2.0 * gripper.clearance_m;
  if (plan.opening_m > gripper.max_opening_m) {
    std::ostringstream why;
    why.precision(3);
    why << "the rock is " << width << " m across; the gripper opens " << gripper.max_opening_m
        << " m";
    plan.reason = why.str();
    return plan;
  }
  const double radius = rock.footprintRadius();
  std::vector<double> ring;
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c) {
      if (!image.hasPoint(r, c)) continue;
      const Eigen::Vector3d p = image.point(r, c);
      const double d = (p - centre).head<2>().norm();
      if (d >= 1.3 * radius && d <= 2.0 * radius) ring.push_back(p.z());
    }
  double ground = centre.z() - rock.size.z();
  if (!ring.empty()) {
    std::nth_element(ring.begin(), ring.begin() + std::ptrdiff_t(ring.size() / 2), ring.end());
    ground = ring[ring.size() / 2];
  }
  plan.centre = {centre.x(), centre.y(), ground};
  plan.ok = true;
  return plan;
}

}  // namespace ambler::sampling

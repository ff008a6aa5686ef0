#pragma once

#include <Eigen/Geometry>
#include <optional>

namespace ambler {

// Solina's superquadric: F = ((x/a1)^(2/e2) + (y/a2)^(2/e2))^(e2/e1) +
// (z/a3)^(2/e1) in the object frame; F < 1 inside, F = 1 on the surface
// (cmu-1990 sampling paper, eq. 5). The simulator's rocks and the sampling fits are these.
struct Superquadric {
  Eigen::Vector3d size{1.0, 1.0, 1.0};                     // a1, a2, a3 [m]
  double eps1 = 1.0;                                       // roundness along z
  double eps2 = 1.0;                                       // roundness in the x-y plane
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // object to world

  double insideOutside(const Eigen::Vector3d& world_point) const;

  // For an upright superquadric (object z along world z): height of its top
  // surface above (x, y), or nothing outside its outline.
  std::optional<double> topHeight(double x, double y) const;

  // The surface point at latitude eta in [-pi/2, pi/2] and longitude omega
  // in [-pi, pi] (the parametric form), in the world.
  Eigen::Vector3d surfacePoint(double eta, double omega) const;

  // How far the shape reaches from its centre along a unit world direction
  // (its support function): the dual of its nested norm, exact for the
  // convex shapes (eps1, eps2 <= 2).
  double reach(const Eigen::Vector3d& direction) const;

  // Radius of a vertical cylinder around the centre that contains it.
  double footprintRadius() const { return size.head<2>().norm(); }
};

}  // namespace ambler

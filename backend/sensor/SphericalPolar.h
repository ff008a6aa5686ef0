#pragma once

#include <Eigen/Core>

namespace ambler::sensor {

// A point in the scanner's non-standard spherical-polar frame: rho is range,
// phi the vertical and theta the horizontal scanning angle [m, rad].
struct SphericalPoint {
  double rho = 0.0;
  double phi = 0.0;
  double theta = 0.0;
};

// krotkov1989 eq. 1: x = rho sin(theta), y = rho cos(phi) cos(theta),
// z = rho sin(phi) cos(theta). y looks along the boresight, z up, x right.
Eigen::Vector3d toCartesian(const SphericalPoint& p);

// Inverse of eq. 1, defined for points with y-z components not both zero;
// returns theta in [-pi/2, pi/2] and phi in (-pi, pi].
SphericalPoint toSpherical(const Eigen::Vector3d& p);

// How rows and columns of a range image map to scanning angles: row r has
// phi = phi_first + r * phi_step, column c has theta = theta_first + c *
// theta_step (radians in memory, degrees in files).
struct ScanGeometry {
  int rows = 0;
  int cols = 0;
  double phi_first = 0.0;
  double phi_step = 0.0;
  double theta_first = 0.0;
  double theta_step = 0.0;

  double phi(double row) const { return phi_first + row * phi_step; }
  double theta(double col) const { return theta_first + col * theta_step; }
  double row(double phi_rad) const { return (phi_rad - phi_first) / phi_step; }
  double col(double theta_rad) const { return (theta_rad - theta_first) / theta_step; }

  // True when (phi, theta) falls on the image, pixel footprints included.
  bool covers(double phi_rad, double theta_rad) const;

  // A geometry of rows x cols pixel centres spread symmetrically over the
  // given fields of view; row 0 looks highest (phi decreases down the image).
  static ScanGeometry symmetric(int rows, int cols, double vertical_fov_rad,
                                double horizontal_fov_rad);
};

}  // namespace ambler::sensor

#include "sensor/SphericalPolar.h"

#include <algorithm>
#include <cmath>

namespace ambler::sensor {

Eigen::Vector3d toCartesian(const SphericalPoint& p) {
  const double ct = std::cos(p.theta);
  return {p.rho * std::sin(p.theta), p.rho * std::cos(p.phi) * ct, p.rho * std::sin(p.phi) * ct};
}

SphericalPoint toSpherical(const Eigen::Vector3d& p) {
  SphericalPoint s;
  s.rho = p.norm();
  if (s.rho == 0.0) return s;
  s.theta = std::asin(std::clamp(p.x() / s.rho, -1.0, 1.0));
  s.phi = std::atan2(p.z(), p.y());
  return s;
}

bool ScanGeometry::covers(double phi_rad, double theta_rad) const {
  const double r = row(phi_rad);
  const double c = col(theta_rad);
  return r >= -0.5 && r <= rows - 0.5 && c >= -0.5 && c <= cols - 0.5;
}

ScanGeometry ScanGeometry::symmetric(int rows, int cols, double vertical_fov_rad,
                                     double horizontal_fov_rad) {
  ScanGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.phi_step = -vertical_fov_rad / rows;
  g.phi_first = vertical_fov_rad / 2 + g.phi_step / 2;
  g.theta_step = horizontal_fov_rad / cols;
  g.theta_first = -horizontal_fov_rad / 2 + g.theta_step / 2;
  return g;
}

}  // namespace ambler::sensor

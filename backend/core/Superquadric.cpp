#include "core/Superquadric.h"

#include <cmath>

namespace ambler {

namespace {

// The planar part of F: (|x/a1|^(2/e2) + |y/a2|^(2/e2))^(e2/e1).
double planarTerm(const Superquadric& s, double x, double y) {
  const double px = std::pow(std::abs(x / s.size.x()), 2.0 / s.eps2);
  const double py = std::pow(std::abs(y / s.size.y()), 2.0 / s.eps2);
  return std::pow(px + py, s.eps2 / s.eps1);
}

}  // namespace

double Superquadric::insideOutside(const Eigen::Vector3d& world_point) const {
  const Eigen::Vector3d p = pose.inverse() * world_point;
  return planarTerm(*this, p.x(), p.y()) + std::pow(std::abs(p.z() / size.z()), 2.0 / eps1);
}

Eigen::Vector3d Superquadric::surfacePoint(double eta, double omega) const {
  auto signedPow = [](double v, double e) { return std::copysign(std::pow(std::abs(v), e), v); };
  const double ce = signedPow(std::cos(eta), eps1);
  return pose * Eigen::Vector3d(size.x() * ce * signedPow(std::cos(omega), eps2),
                                size.y() * ce * signedPow(std::sin(omega), eps2),
                                size.z() * signedPow(std::sin(eta), eps1));
}

std::optional<double> Superquadric::topHeight(double x, double y) const {
  const Eigen::Vector3d local =
      pose.linear().transpose() * (Eigen::Vector3d(x, y, 0) - pose.translation());
  const double g = planarTerm(*this, local.x(), local.y());
  if (g >= 1.0) return std::nullopt;
  return pose.translation().z() + size.z() * std::pow(1.0 - g, eps1 / 2.0);
}

}  // namespace ambler

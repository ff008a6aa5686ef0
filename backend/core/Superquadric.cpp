#include "core/Superquadric.h"

#include <algorithm>
#include <cmath>

namespace ambler {

namespace {

// The planar part of F: (|x/a1|^(2/e2) + |y/a2|^(2/e2))^(e2/e1).
double planarTerm(const Superquadric& s, double x, double y) {
  const double px = std::pow(std::abs(x / s.size.x()), 2.0 / s.eps2);
  const double py = std::pow(std::abs(y / s.size.y()), 2.0 / s.eps2);
  return std::pow(px + py, s.eps2 / s.eps1);
}

// The lp norm of (x, y), scaled so that a large p does not overflow.
double lpNorm(double x, double y, double p) {
  const double m = std::max(std::abs(x), std::abs(y));
  if (m == 0) return 0;
  return m * std::pow(std::pow(std::abs(x) / m, p) + std::pow(std::abs(y) / m, p), 1 / p);
}

}  // namespace

double Superquadric::reach(const Eigen::Vector3d& direction) const {
  // F^(eps1/2) is the 2/eps1 norm of (the 2/eps2 norm of (x/a1, y/a2), z/a3);
  // the dual exponent of p = 2/eps is 2/(2 - eps).
  const Eigen::Vector3d u = pose.linear().transpose() * direction;
  const auto dual = [](double eps) { return 2 / (2 - std::min(eps, 1.99)); };
  const double across = lpNorm(size.x() * u.x(), size.y() * u.y(), dual(eps2));
  return lpNorm(across, size.z() * u.z(), dual(eps1));
}

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

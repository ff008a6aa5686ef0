#include "gait/RoverModel.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::gait {

Eigen::Vector3d RoverModel::footInBody(int leg, const LegJoints& q) const {
  const Eigen::Vector2d p =
      shaftOf(leg) +
      q.extension_m * Eigen::Vector2d(std::cos(q.rotation_rad), std::sin(q.rotation_rad));
  return {p.x(), p.y(), -q.vertical_m};
}

LegJoints RoverModel::jointsFor(int leg, const Eigen::Vector3d& foot) const {
  const Eigen::Vector2d d = foot.head<2>() - shaftOf(leg);
  return {std::atan2(d.y(), d.x()), d.norm(), -foot.z()};
}

bool RoverModel::withinLimits(const LegJoints& q) const {
  return q.extension_m >= extension_min_m - 1e-9 && q.extension_m <= extension_max_m + 1e-9 &&
         q.vertical_m >= vertical_min_m - 1e-9 && q.vertical_m <= vertical_max_m + 1e-9;
}

double RoverModel::beyondLimits(const LegJoints& q) const {
  const auto beyond = [](double v, double lo, double hi) {
    return std::max(0.0, lo - v) + std::max(0.0, v - hi);
  };
  return beyond(q.extension_m, extension_min_m, extension_max_m) +
         beyond(q.vertical_m, vertical_min_m, vertical_max_m);
}

double RoverModel::legSegmentS(const LegJoints& from, const LegJoints& to) const {
  const double d_rot = std::remainder(to.rotation_rad - from.rotation_rad, 2 * M_PI);
  return std::max({std::abs(d_rot) / rotation_speed_rad_s,
                   std::abs(to.extension_m - from.extension_m) / extension_speed_m_s,
                   std::abs(to.vertical_m - from.vertical_m) / vertical_speed_m_s});
}

namespace {

// Duration of a trapezoidal (or triangular) velocity profile.
double trapezoid(double distance, double v_max, double accel) {
  if (distance <= 0) return 0.0;
  if (distance >= v_max * v_max / accel) return distance / v_max + v_max / accel;
  return 2.0 * std::sqrt(distance / accel);
}

}  // namespace

double RoverModel::bodyMoveS(double distance_m, double turn_rad, double raise_m) const {
  return std::max({trapezoid(std::abs(distance_m), body_speed_m_s, body_accel_m_s2),
                   trapezoid(std::abs(turn_rad), body_turn_speed_rad_s, body_accel_m_s2),
                   std::abs(raise_m) / vertical_speed_m_s});
}

void validate(const RoverModel& m) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  for (const auto& s : m.shafts) require(s.allFinite(), "shafts must be finite");
  require((m.shafts[0] - m.shafts[1]).norm() > 0.1, "shafts must be at least 0.1 m apart");
  require(m.extension_min_m > 0 && m.extension_max_m > m.extension_min_m,
          "extension_m must be 0 < min < max");
  require(m.vertical_min_m >= 0 && m.vertical_max_m > m.vertical_min_m,
          "vertical_m must be 0 <= min < max");
  require(m.foot_diameter_m > 0 && m.foot_diameter_m < 2, "foot_diameter_m must be in (0, 2)");
  require(m.link_plane_nominal_m > m.vertical_min_m && m.link_plane_nominal_m < m.vertical_max_m,
          "link_plane_nominal_m must lie inside vertical_m");
  require(m.mass_kg > 0, "mass_kg must be > 0");
  require(m.centre_of_gravity.allFinite(), "centre_of_gravity_m must be finite");
  require(m.body_keepout_half.minCoeff() >= 0, "body_keepout_half_m must be >= 0");
  require(m.shaft_clearance_m >= 0 && m.min_leg_separation_m >= m.foot_diameter_m,
          "min_leg_separation_m must be at least the foot diameter");
  for (double v : {m.rotation_speed_rad_s, m.extension_speed_m_s, m.vertical_speed_m_s,
                   m.body_speed_m_s, m.body_turn_speed_rad_s, m.body_accel_m_s2})
    require(v > 0 && std::isfinite(v), "joint and body speeds must be > 0");
}

}  // namespace ambler::gait

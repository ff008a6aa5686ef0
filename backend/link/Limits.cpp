#include "link/Limits.h"

#include <cmath>
#include <sstream>

namespace ambler::link {

namespace {

std::string format(double value, int precision = 2) {
  std::ostringstream s;
  s.precision(precision);
  s << std::fixed << value;
  return s.str();
}

// Joints planned exactly at a limit come out a rounding error beyond it.
constexpr double kRounding = 1e-9;

std::string check(const LegMove& m, const gait::RoverModel& model, const gait::GaitOptions&) {
  for (std::size_t i = 0; i < m.waypoints.size(); ++i) {
    const auto& q = m.waypoints[i];
    const std::string where =
        "leg " + std::to_string(m.leg) + " waypoint " + std::to_string(i + 1) + ": ";
    if (q.extension_m < model.extension_min_m - kRounding ||
        q.extension_m > model.extension_max_m + kRounding)
      return where + "extension " + format(q.extension_m) + " m outside " +
             format(model.extension_min_m) + "-" + format(model.extension_max_m) + " m";
    if (q.vertical_m < model.vertical_min_m - kRounding ||
        q.vertical_m > model.vertical_max_m + kRounding)
      return where + "vertical " + format(q.vertical_m) + " m outside " +
             format(model.vertical_min_m) + "-" + format(model.vertical_max_m) + " m";
  }
  return {};
}

std::string check(const BodyMove& m, const gait::RoverModel&, const gait::GaitOptions& gait) {
  const double advance = std::hypot(m.x_m, m.y_m);
  if (advance > gait.max_body_advance_m + kRounding)
    return "body advance " + format(advance) + " m over the " + format(gait.max_body_advance_m) +
           " m limit";
  if (std::abs(m.rotation_rad) > gait.max_body_turn_rad + kRounding)
    return "body turn " + format(m.rotation_rad * 180 / M_PI, 1) + " deg over the " +
           format(gait.max_body_turn_rad * 180 / M_PI, 1) + " deg limit";
  return {};
}

std::string check(const Grasp& m, const gait::RoverModel&, const gait::GaitOptions&) {
  if (m.opening_m <= 0) return "grasp opening " + format(m.opening_m) + " m is not positive";
  return {};
}

// Commands that move nothing have no limits.
template <typename Body>
std::string check(const Body&, const gait::RoverModel&, const gait::GaitOptions&) {
  return {};
}

}  // namespace

Refusal outsideLimits(const CommandBody& command, const gait::RoverModel& model,
                      const gait::GaitOptions& gait) {
  std::string why = std::visit([&](const auto& body) { return check(body, model, gait); }, command);
  return why.empty() ? Refusal{} : Refusal::because(std::move(why));
}

}  // namespace ambler::link

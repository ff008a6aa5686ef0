#include "executive/ReportedStance.h"

#include <algorithm>

namespace ambler::executive {

void RoverReport::take(const link::Telemetry& message) {
  if (const auto* leg = std::get_if<link::LegState>(&message.body)) {
    if (leg->leg < 0 || leg->leg >= gait::kLegCount) return;
    legs[std::size_t(leg->leg)] = *leg;
    leg_time_s[std::size_t(leg->leg)] = message.time_s;
  } else if (const auto* b = std::get_if<link::BodyState>(&message.body)) {
    body = *b;
    body_time_s = message.time_s;
  }
}

bool RoverReport::reportedSince(double rover_time_s) const {
  return body_time_s >= rover_time_s && !moving() &&
         std::all_of(leg_time_s.begin(), leg_time_s.end(),
                     [&](double t) { return t >= rover_time_s; });
}

std::optional<gait::Stance> RoverReport::stance(const gait::RoverModel& model) const {
  if (!body) return std::nullopt;
  gait::Stance s;
  s.body = {{body->x_m, body->y_m}, body->heading_rad, body->z_m};
  for (int i = 0; i < gait::kLegCount; ++i) {
    const auto& leg = legs[std::size_t(i)];
    if (!leg) return std::nullopt;
    s.feet[std::size_t(i)] = s.body.toWorld(model.footInBody(i, leg->joints));
    s.supporting[std::size_t(i)] = leg->contact;
  }
  return s;
}

std::optional<RoverSample> RoverReport::sample(const gait::RoverModel& model, double time_s) const {
  auto s = stance(model);
  if (!s) return std::nullopt;
  RoverSample out{time_s, *s, {}, moving()};
  for (int i = 0; i < gait::kLegCount; ++i)
    out.force_n[std::size_t(i)] = legs[std::size_t(i)]->force_n;
  return out;
}

}  // namespace ambler::executive

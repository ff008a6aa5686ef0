#pragma once

#include <array>
#include <optional>

#include "gait/Stance.h"
#include "link/Messages.h"

namespace ambler::executive {

// The rover at one moment, as plotted: its stance and each foot's load.
struct RoverSample {
  double time_s = 0.0;
  gait::Stance stance;
  std::array<double, gait::kLegCount> force_n{};
};

// What the rover reports of its legs and body, newest of each.
struct RoverReport {
  std::array<std::optional<link::LegState>, gait::kLegCount> legs{};
  std::optional<link::BodyState> body;

  void take(const link::Telemetry& message);  // keeps leg and body states
  // The stance those reports describe (feet by forward kinematics); none
  // until the body and every leg have reported.
  std::optional<gait::Stance> stance(const gait::RoverModel& model) const;
  std::optional<RoverSample> sample(const gait::RoverModel& model, double time_s) const;
};

}  // namespace ambler::executive

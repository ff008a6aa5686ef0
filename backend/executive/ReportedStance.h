#pragma once

#include <array>
#include <optional>

#include "gait/Stance.h"
#include "link/Messages.h"

namespace ambler::executive {

// What the rover reports of its legs and body, newest of each.
struct RoverReport {
  std::array<std::optional<link::LegState>, gait::kLegCount> legs{};
  std::optional<link::BodyState> body;

  void take(const link::Telemetry& message);  // keeps leg and body states
  // The stance those reports describe (feet by forward kinematics); none
  // until the body and every leg have reported.
  std::optional<gait::Stance> stance(const gait::RoverModel& model) const;
};

}  // namespace ambler::executive

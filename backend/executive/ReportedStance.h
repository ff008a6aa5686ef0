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
  // The rover says a move is under way: the stance is where it began.
  bool moving = false;
};

// What the rover reports of its legs and body, newest of each.
struct RoverReport {
  std::array<std::optional<link::LegState>, gait::kLegCount> legs{};
  std::optional<link::BodyState> body;
  // The rover times of those reports.
  std::array<double, gait::kLegCount> leg_time_s;
  double body_time_s = -1e300;

  RoverReport() { leg_time_s.fill(-1e300); }
  void take(const link::Telemetry& message);  // keeps leg and body states
  // Whether the body and every leg have reported since `rover_time_s`, the
  // body no longer moving: each travels on its own DDS topic, and over a
  // network they may come in any order relative to each other and to the
  // acknowledgements.
  bool reportedSince(double rover_time_s) const;
  // The rover's last word on its body is that a move is under way, this
  // console's or another's (docs/dds.md §7).
  bool moving() const { return body && body->moving; }
  // The stance those reports describe (feet by forward kinematics); none
  // until the body and every leg have reported.
  std::optional<gait::Stance> stance(const gait::RoverModel& model) const;
  std::optional<RoverSample> sample(const gait::RoverModel& model, double time_s) const;
};

}  // namespace ambler::executive

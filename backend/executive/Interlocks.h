#pragma once

// The checks a step passes on the ground before any of its commands is
// sent, whether an operator approved it or auto-approve is on:
// joint limits, reach, the conservative support polygon with margin, and a
// foothold on known ground.

#include <string>
#include <vector>

#include "gait/GaitPlanner.h"
#include "link/Messages.h"
#include "terrain/ElevationMap.h"

namespace ambler::executive {

struct InterlockCheck {
  std::string name;  // "plan", "joint limits", "reach", "stability", "foothold terrain"
  bool passed = false;
  std::string detail;  // the figures, with units, either way
};

struct InterlockReport {
  std::vector<InterlockCheck> checks;
  bool passed() const;
  // "reach: ..." for the first check that failed; empty when all passed.
  std::string firstFailure() const;
};

// The commands that carry out `plan` from `from`: the leg move (unless the
// step is a body move only), then the body move.
std::vector<link::CommandBody> stepCommands(const gait::StepPlan& plan, const gait::Stance& from);

// A length as the executive's messages give it: "0.125 m".
std::string metres(double value);

InterlockReport checkInterlocks(const gait::StepPlan& plan, const gait::Stance& from,
                                const std::vector<link::CommandBody>& commands,
                                const terrain::ElevationMap& map, const gait::GaitContext& context);

}  // namespace ambler::executive
